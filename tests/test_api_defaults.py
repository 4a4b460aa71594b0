"""One option, one default: an option several public entry points take has the same
default at all of them, the command lines included, or a documented reason to differ
(docs/api.md, "Options shared by several entry points", lists both).

The public API is walked as the API pages list it (docs/conf.py), so a new entry point
with a shared option is checked without being named here.
"""

import dataclasses
import importlib
import inspect

import pytest
from public_api import public_methods, public_objects

#: the options shared by several entry points, and their one default
DEFAULTS = {
    "continuation": True, "progress": False, "excitation": None, "method": "auto",
    "seed": 0, "level": 0.9, "executor": None, "check_passive": True,
    "read_options": None, "estimator": None, "weights": None, "n_top": 3, "dt": None,
    "gap": 0.0, "velocity1": 0.0, "velocity2": 0.0, "uncertainty": False, "extend": None,
    "passive": "auto", "quantity": None, "outputs": None, "contact": "Rigid()",
}

#: where a default differs, and why (docs/api.md says the same)
DIFFERENT = {
    ("impactpred.predict", "continuation"): "auto",    # decided per body from a first solve
    ("impactpred.predict", "contact"): "rigid",        # a spec string, parsed to Rigid()
    ("impactpred.choose_dt", "method"): "convolution",  # the step that resolves the bodies
    ("modalid.ModalFit", "method"): "lscf",            # another option: the fit's estimator
    ("impactpred.parallel.Pool.map", "progress"): None,  # a bar to advance, not a switch
    # a bar once a solve has taken 10 s: a short run prints nothing
    ("impactpred.solve_impact", "progress"): "auto",
    ("impactpred.predict", "progress"): "auto",
    # data_synth draws measurement noise: fresh at each call unless seeded (numpy's rule)
    ("data_synth.synthetic_frf", "seed"): None,
    ("data_synth.synthetic_impulse_response", "seed"): None,
    ("data_synth.synthetic_hammer_test", "seed"): None,
    ("data_synth.random_modal_model", "seed"): None,
    ("impactpred.benchmark.run_case", "uncertainty"): True,   # a case measures coverage
    # the extent for a model with no fit to count its modes (16 band tops), and the smooth
    # tail's design, in units of omega_a
    ("impactpred.truncation.continue_above_band", "extend"): 16.0,
    ("impactpred.truncation.smooth_tail_design", "extend"): 4.0,
    # the fit's steps once it has decided whether the FRF is a driving point
    ("modalid.stabilization.select_by_information", "passive"): True,
    ("modalid.stabilization.prefix_information", "passive"): True,
    # the quantity of values given or computed, not of a file to read
    ("modalid.FRFData", "quantity"): "receptance",
    ("modalid.FRFSet", "quantity"): "receptance",
    ("modalid.ModalModel.frf", "quantity"): "receptance",
    ("modalid.MultiOutputModalModel.frf", "quantity"): "receptance",
    ("data_synth.ExactModel.frf", "quantity"): "receptance",
    ("data_synth.synthetic_frf", "quantity"): "receptance",
    ("impactpred.PointResponse.plot", "quantity"): "acceleration",
}

#: records (results, settings holders): their fields' defaults are not options
RECORDS = ("impactpred.ImpactResult", "impactpred.Prediction", "impactpred.DamperResult",
           "impactpred.PointResponse", "impactpred.uncertainty.UncertaintyBand",
           "impactpred.truncation.ContinuationInfo", "impactpred.truncation.TailDesign",
           "impactpred.benchmark.Case", "impactpred.paper.PaperCase")


def _entry_points():
    """``(qualified name, callable)`` of every public function, class and method."""
    for qualified, obj in public_objects():
        if inspect.isclass(obj):
            if qualified not in RECORDS:
                yield qualified, obj
            for attr, _ in public_methods(obj):
                yield f"{qualified}.{attr}", getattr(obj, attr)
        elif callable(obj):
            yield qualified, obj


def _defaults():
    """``{(entry point, option): default}`` of the shared options that have a default."""
    found = {}
    for qualified, obj in _entry_points():
        try:
            parameters = inspect.signature(obj).parameters.values()
        except (TypeError, ValueError):
            continue
        for p in parameters:
            if p.name in DEFAULTS and p.default is not inspect.Parameter.empty:
                default = p.default
                if dataclasses.is_dataclass(default) and not isinstance(default, type):
                    default = repr(default)
                found[(qualified, p.name)] = default
    return found


def test_every_shared_option_has_one_default_or_a_documented_reason():
    found = _defaults()
    wrong = {key: value for key, value in found.items()
             if key not in DIFFERENT and value != DEFAULTS[key[1]]}
    assert not wrong, f"defaults that differ from the shared one, undocumented: {wrong}"
    changed = {key: (found.get(key, "gone"), value) for key, value in DIFFERENT.items()
               if found.get(key, "gone") != value}
    assert not changed, f"documented differences that no longer hold (now, listed): {changed}"
    # the options the issue named are really shared
    for option in ("continuation", "progress", "method", "seed", "executor"):
        assert sum(1 for _, name in found if name == option) >= 2, option


def test_the_options_the_issue_named():
    from impactpred import ImpactDamper, predict, solve_impact
    from impactpred.damper import sweep
    from impactpred.predict import parse_contact
    from modalid import ModalFit

    found = _defaults()
    # continuation: True wherever one body or fit is at hand; predict's "auto" needs a solve
    assert {k: v for k, v in found.items() if k[1] == "continuation"} == {
        ("impactpred.predict", "continuation"): "auto",
        ("impactpred.predict.parse_body", "continuation"): True,
        ("impactpred.truncation.identified_model", "continuation"): True,
        ("impactpred.uncertainty.uncertainty_band", "continuation"): True}
    # progress: off in the library
    for entry in (ModalFit.__init__, ImpactDamper.simulate, sweep,
                  importlib.import_module("impactpred.benchmark").run_benchmark):
        assert inspect.signature(entry).parameters["progress"].default is False, entry
    # excitation: required at its one entry point (no default), named when missing
    from data_synth import SpringMass
    assert inspect.signature(ImpactDamper).parameters["excitation"].default is \
        inspect.Parameter.empty
    with pytest.raises(TypeError, match="missing 1 required keyword-only argument: "
                                        "'excitation'"):
        ImpactDamper(SpringMass(1.0, 100.0), damper_mass=0.1, clearance=1e-3)
    with pytest.raises(TypeError, match="excitation must be a HarmonicForce"):
        ImpactDamper(SpringMass(1.0, 100.0), damper_mass=0.1, clearance=1e-3, excitation=None)
    # contact: predict's spec string is solve_impact's law
    assert parse_contact(inspect.signature(predict).parameters["contact"].default) == \
        inspect.signature(solve_impact).parameters["contact"].default


def test_the_command_lines_take_the_librarys_defaults(monkeypatch, tmp_path):
    """``impactpred predict`` parses to predict's defaults; both command lines fit with
    progress on (the one thing they turn on), with the same ModalFit settings."""
    import numpy as np

    from data_synth import SpringMass, synthetic_frf
    from impactpred.cli import _run_predict, build_parser
    from modalid import ModalFit, write_frf
    from modalid.cli import main as modalid_main

    predict_module = importlib.import_module("impactpred.predict")   # not the function

    parameters = inspect.signature(predict_module.predict).parameters
    args = build_parser().parse_args(["predict", "a.csv", "b.csv", "--t-end", "1"])
    for flag, option in (("v1", "velocity1"), ("v2", "velocity2"), ("gap", "gap"),
                         ("contact", "contact"), ("dt", "dt"), ("method", "method"),
                         ("continuation", "continuation"), ("uncertainty", "uncertainty")):
        assert getattr(args, flag) == parameters[option].default, flag
    assert (not args.no_passivity_check) == parameters["check_passive"].default
    bench = build_parser().parse_args(["benchmark"])
    run_benchmark = importlib.import_module("impactpred.benchmark").run_benchmark
    benchmark = inspect.signature(run_benchmark).parameters
    assert tuple(bench.bands) == benchmark["bands"].default
    assert bench.workers == benchmark["workers"].default
    assert tuple(n / 100 for n in bench.noise) == benchmark["noises"].default

    seen = {}

    def capture(*args, **kwargs):
        seen["predict"] = kwargs["estimator"]
        raise ValueError("captured")

    monkeypatch.setattr(predict_module, "predict", capture)
    with pytest.raises(ValueError, match="captured"):
        _run_predict(build_parser().parse_args(
            ["predict", "a.csv", "b.csv", "--t-end", "1", "--n-modes", "4"]))

    def fit(self, data, weights=None):
        seen["fit"] = self
        raise ValueError("captured")

    monkeypatch.setattr(ModalFit, "fit", fit)
    path = tmp_path / "frf.csv"
    write_frf(path, synthetic_frf(SpringMass(1.0, 1e4).modal_model(1),
                                  np.linspace(1.0, 40.0, 200)))
    assert modalid_main(["fit", str(path), "--n-modes", "4"]) == 2
    for estimator in (seen["predict"], seen["fit"]):
        assert estimator.get_params() == ModalFit(n_modes=4, progress=True).get_params()
