"""modalid.FRFSet and read_frf_set: validation, rows, conversions, readers, refused inputs."""

import warnings
from pathlib import Path

import numpy as np
import pyuff
import pytest

from modalid import FRFData, FRFSet, read_frf, read_frf_set, write_frf

DATA = Path(__file__).parent / "data"
MEASURED = [DATA / f"meas_point_{k}.txt" for k in (1, 2, 3)]


def make_set(n_out=3, n=50, seed=0, **kw):
    rng = np.random.default_rng(seed)
    f = np.arange(n) * 2.0
    values = rng.normal(size=(n_out, n)) + 1j * rng.normal(size=(n_out, n))
    return FRFSet(f, values, **kw)


# ------------------------------------------------------------------ the object
def test_rows_labels_and_driving_point():
    s = make_set(outputs=["a", "b", "c"], driving_point="b", quantity="mobility")
    assert s.n_outputs == 3 and len(s) == 50 and s.driving_point == 1
    assert s.outputs == ("a", "b", "c")
    row = s.row("c")
    assert isinstance(row, FRFData) and row.quantity == "mobility"
    np.testing.assert_array_equal(row.values, s.values[2])
    np.testing.assert_array_equal(s.row(-1).values, s.values[2])
    np.testing.assert_array_equal(s.driving.values, s.values[1])
    assert "driving_point='b'" in repr(s)
    with pytest.raises(AttributeError, match="immutable"):
        s.quantity = "receptance"
    with pytest.raises(ValueError, match="read-only"):
        s.values[0, 0] = 1.0


@pytest.mark.parametrize("output, error, match", [
    (3, ValueError, "output index 3 is out of range for 3 outputs"),
    (-4, ValueError, "output index -4 is out of range"),
    ("z", ValueError, "no output labelled 'z'"),
    (1.0, TypeError, "int row index or a str label, got 1.0"),
])
def test_output_out_of_range(output, error, match):
    s = make_set()
    with pytest.raises(error, match=match):
        s.row(output)
    with pytest.raises(error, match=match):
        FRFSet(s.freq_hz, s.values, driving_point=output)


def test_driving_point_none_is_refused_where_one_is_needed():
    s = make_set(driving_point=None)
    assert s.driving_point is None and "driving_point=None" in repr(s)
    with pytest.raises(ValueError, match="needs a driving point .* driving_point=None"):
        s.driving  # noqa: B018


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(values=np.ones(50)), ValueError, "values must be 2-D"),
    (dict(values=np.ones((2, 49))), ValueError, "one column per frequency line \\(50\\)"),
    (dict(values=np.ones((0, 50))), ValueError, "at least one output row"),
    (dict(values=np.full((2, 50), np.nan)), ValueError, "values must be finite"),
    (dict(coherence=np.ones((2, 49))), ValueError, "coherence must have the shape"),
    (dict(coherence=np.full((2, 50), 1.5)), ValueError,
     "coherence must lie in \\[0, 1\\], got 1.5"),
    (dict(outputs=["a", "a"]), ValueError, "unique"),
    (dict(outputs=["a"]), ValueError, "must hold 2 labels"),
    (dict(outputs="ab"), TypeError, "sequence of 2 str labels"),
    (dict(quantity="force"), ValueError, "quantity must be one of"),
    (dict(freq_hz=np.arange(50.0)[::-1]), ValueError, "strictly increasing"),
])
def test_bad_input_is_refused(kwargs, error, match):
    args = dict(freq_hz=np.arange(50.0), values=np.ones((2, 50)))
    args.update(kwargs)
    with pytest.raises(error, match=match):
        FRFSet(args.pop("freq_hz"), args.pop("values"), **args)


@pytest.mark.parametrize("index, error, match", [
    (3, TypeError, r"got the integer 3: for one line pass \[3\]"),
    ("a", TypeError, "a slice, a boolean mask or an array of line indices"),
    ([True, False], ValueError, "as a mask must hold 20 values .one per line., got 2"),
    ([0, 25], ValueError, "line indices out of range for 20 lines"),
])
def test_a_bad_line_selection_is_refused_naming_it(index, error, match):
    """``select(3)`` said "freq_hz must be 1-D, got shape ()"; ``select('a')`` raised
    IndexError. Both FRFData and FRFSet."""
    data = make_set(n=20)
    for target in (data, data.row(0)):
        with pytest.raises(error, match=match):
            target.select(index)
    assert data.select([0, -1]).freq_hz.size == 2


def test_none_for_the_rows_or_the_files_is_refused_naming_it():
    """Both said "'NoneType' object is not iterable"."""
    with pytest.raises(TypeError, match="frfs must be an FRFData or a list of them, got "
                                        "NoneType"):
        FRFSet.from_frfs(None)
    with pytest.raises(TypeError, match="path_or_paths must be a path or a list of paths, "
                                        "got NoneType"):
        read_frf_set(None)
    one = make_set(n=20).row(0)
    assert len(FRFSet.from_frfs(one).outputs) == 1            # one FRFData is a set of one


def test_from_frfs_refuses_different_grids_and_quantities():
    f = np.arange(1.0, 101.0)
    a, b = FRFData(f, np.ones(100)), FRFData(f, 2 * np.ones(100))
    s = FRFSet.from_frfs([a, b], driving_point=1, outputs=["x", "y"])
    assert s.driving_point == 1 and s.coherence is None
    shifted = FRFData(f + 0.5, np.ones(100))
    with pytest.raises(ValueError, match=r"rows 0 and 2 are on different frequency grids: "
                                         r"line 0 is at 1.0 Hz in one and 1.5 Hz"):
        FRFSet.from_frfs([a, b, shifted])
    with pytest.raises(ValueError, match="100 lines 1-100 Hz against 50 lines"):
        FRFSet.from_frfs([a, a.select(slice(0, 50))])
    with pytest.raises(ValueError, match="row 1 is mobility, row 0 is receptance"):
        FRFSet.from_frfs([a, FRFData(f, np.ones(100), quantity="mobility")])
    with pytest.raises(TypeError, match=r"frfs\[1\] must be an FRFData"):
        FRFSet.from_frfs([a, np.ones(100)])


def test_conversions_band_and_coherence():
    f = np.arange(0.0, 100.0, 0.5)
    rng = np.random.default_rng(3)
    values = rng.normal(size=(2, f.size)) + 1j * rng.normal(size=(2, f.size))
    coh = rng.uniform(0, 1, (2, f.size))
    s = FRFSet(f, values, quantity="accelerance", coherence=coh, outputs=["p", "q"])
    with pytest.warns(UserWarning, match="dropped the 0 Hz line"):
        rec = s.to_receptance()
    assert rec.quantity == "receptance" and len(rec) == f.size - 1
    np.testing.assert_allclose(rec.values, values[:, 1:] / -(2 * np.pi * f[1:]) ** 2)
    np.testing.assert_array_equal(rec.coherence, coh[:, 1:])
    np.testing.assert_allclose(rec.convert("accelerance").values, values[:, 1:], rtol=1e-14)
    b = s.band((10, 20))
    assert b.freq_hz[0] == 10 and b.freq_hz[-1] == 20 and b.outputs == ("p", "q")
    for i in range(2):
        np.testing.assert_array_equal(b.row(i).values, s.row(i).band((10, 20)).values)


def test_plot_returns_the_axes():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    assert make_set(n=20).select(slice(1, None)).plot(ax=ax) is ax
    assert len(ax.lines) == 3
    plt.close(fig)


# ------------------------------------------------------------------ readers
def test_read_the_measured_beam_points():
    s = read_frf_set(MEASURED, format="complex-lines", freq_hz=np.arange(1001.0),
                     quantity="accelerance", driving_point=0)
    assert s.outputs == ("meas_point_1", "meas_point_2", "meas_point_3")
    assert s.n_outputs == 3 and len(s) == 1001 and s.driving_point == 0
    assert s.values[0, 0] == complex("(-0.0774752256830106+2.6838208936737454e-08j)")
    with pytest.raises(ValueError, match="do not say which FRF is the driving point"):
        read_frf_set(MEASURED, freq_hz=np.arange(1001.0), quantity="accelerance")
    with pytest.raises(ValueError, match="output index 3 is out of range"):
        read_frf_set(MEASURED, freq_hz=np.arange(1001.0), quantity="accelerance",
                     driving_point=3)


def write_csv(path, f, values, header):
    rows = [",".join(repr(float(x)) for x in row) for row in zip(f, *values)]
    path.write_text("# quantity: mobility\n" + header + "\n" + "\n".join(rows) + "\n")


def test_read_csv_with_several_frf_columns(tmp_path):
    s0 = make_set(n=40)
    f = s0.freq_hz[1:]
    v = s0.values[:, 1:]
    cols = [v[0].real, v[0].imag, v[1].real, v[1].imag,
            20 * np.log10(np.abs(v[2])), np.degrees(np.angle(v[2]))]
    write_csv(tmp_path / "set.csv", f, cols,
              "freq_hz,p1_real,p1_imag,P2 Real,P2 Imag,mag_db_3,phase_deg_3")
    s = read_frf_set(tmp_path / "set.csv", driving_point="P2")
    assert s.outputs == ("p1", "P2", "3") and s.driving_point == 1
    assert s.quantity == "mobility"
    np.testing.assert_allclose(s.values, v, rtol=1e-12)
    # a single-FRF CSV reads as a set of one row
    write_csv(tmp_path / "one.csv", f, [v[0].real, v[0].imag], "freq_hz,real,imag")
    one = read_frf_set(tmp_path / "one.csv", driving_point=0)
    assert one.n_outputs == 1 and one.outputs == ("one",)


def test_read_csv_groups_without_one_frequency_column(tmp_path):
    f = np.arange(1.0, 11.0)
    write_csv(tmp_path / "bad.csv", f, [f, f, f, f], "a_real,a_imag,b_real,b_imag")
    with pytest.raises(ValueError, match="exactly one frequency column"):
        read_frf_set(tmp_path / "bad.csv", driving_point=0)


def write_uffs(tmp_path, pairs, freq=None):
    freq = np.arange(1.0, 65.0) if freq is None else freq
    paths = []
    for k, (rsp, ref) in enumerate(pairs):
        path = tmp_path / f"r{k}.uff"
        values = (k + 1) * (1.0 + 1j * freq)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ResourceWarning)
            write_frf(path, FRFData(freq, values, quantity="accelerance"), binary=True,
                      response=(rsp, 3), reference=(ref, 3))
        paths.append(path)
    return paths


def test_read_uff_records_find_the_driving_point(tmp_path):
    # roving hammer: the response is fixed at node 2, the hammer hits nodes 1, 2, 3
    paths = write_uffs(tmp_path, [(2, 1), (2, 2), (2, 3)])
    s = read_frf_set(paths)
    assert s.outputs == ("1+Z", "2+Z", "3+Z") and s.driving_point == 1
    np.testing.assert_allclose(s.values[2], 3 * (1 + 1j * s.freq_hz))
    # the same records in one file (UFF files are sequences of datasets)
    one = tmp_path / "all.uff"
    one.write_bytes(b"".join(p.read_bytes() for p in paths))
    s1 = read_frf_set(one)
    assert s1.outputs == s.outputs and s1.driving_point == 1
    np.testing.assert_array_equal(s1.values, s.values)


def test_read_uff_without_or_with_two_driving_points(tmp_path):
    paths = write_uffs(tmp_path, [(1, 2), (3, 2)])
    with pytest.raises(ValueError, match="no record has its response at its reference.s "
                                         "node and axis"):
        read_frf_set(paths)
    assert read_frf_set(paths, driving_point=None).driving_point is None
    twice = write_uffs(tmp_path, [(1, 1), (1, 1)])
    with pytest.raises(ValueError, match=r"records \[0, 1\] have"):
        read_frf_set(twice)


def test_read_refuses_files_on_different_grids(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    (a,) = write_uffs(tmp_path / "a", [(1, 1)])
    (b,) = write_uffs(tmp_path / "b", [(2, 1)], freq=np.arange(1.0, 65.0) * 1.5)
    with pytest.raises(ValueError, match=r"a/r0.uff and .*b/r0.uff are on different frequency "
                                         r"grids: line 0 is at 1.0 Hz in one and 1.5 Hz"):
        read_frf_set([a, b])


def test_frf_data_and_sets_pickle_through_their_constructors():
    """A fitted ModalFit keeps its data: it must pickle (process pools, joblib)."""
    import pickle

    one = FRFData([1.0, 2.0], [1 + 1j, 2j], quantity="mobility", coherence=[0.9, 1.0],
                  excitation=[4.0, 3.0])
    back = pickle.loads(pickle.dumps(one))
    assert np.array_equal(back.values, one.values) and back.quantity == "mobility"
    assert np.array_equal(back.coherence, one.coherence)
    assert np.array_equal(back.excitation, one.excitation)
    data = FRFSet([1.0, 2.0], [[1 + 1j, 2j], [3.0, 4.0]], outputs=("a", "b"), driving_point=1)
    again = pickle.loads(pickle.dumps(data))
    assert again.outputs == ("a", "b") and again.driving_point == 1
    assert np.array_equal(again.values, data.values)


def test_auto_driving_point_takes_a_record_along_the_opposite_direction_negated(tmp_path):
    """Response -Z at the reference node +Z holds -H: read negated, it is the driving point
    (its values the +Z/+Z FRF, as written: write_frf stores it negated), its label along
    +Z; the other record read as stored."""
    freq = np.arange(1.0, 101.0, 2.0)
    frf = FRFData(freq, 1.0 / (1.0 - (freq / 40.0) ** 2 + 0.02j * freq / 40.0))
    write_frf(tmp_path / "a.uff", frf, response=(1, -3), reference=(1, 3))
    write_frf(tmp_path / "b.uff", frf, response=(2, 3), reference=(1, 3))
    data = read_frf_set([tmp_path / "a.uff", tmp_path / "b.uff"])
    assert data.driving_point == 0
    np.testing.assert_allclose(data.values, [frf.values] * 2, rtol=1e-11)  # ASCII: 12 digits
    assert data.outputs == ("1+Z", "2+Z")
    stored = pyuff.UFF(str(tmp_path / "a.uff")).read_sets(0)["data"]
    np.testing.assert_allclose(stored, -frf.values, rtol=1e-11)


def test_frf_data_states_how_it_was_measured_and_keeps_it():
    """``FRFData(window_decay_rate=..., record_length=...)``: kept by select, band,
    conversion and pickling; a negative, zero or non-finite value is refused, naming it;
    an FRFSet of windowed FRFs warns that its common-pole fit does not model the
    window."""
    import pickle

    freq = np.array([0.0, 1.0, 2.0, 3.0])
    one = FRFData(freq, [1.0, 1 + 1j, 2j, 3.0], quantity="accelerance",
                  window_decay_rate=4.6, record_length=1.0)
    with pytest.warns(UserWarning, match="dropped the 0 Hz line"):
        converted = one.to_receptance()
    for kept in (one.band((1.0, 2.0)), one.select([0, 2]), converted,
                 pickle.loads(pickle.dumps(one))):
        assert (kept.window_decay_rate, kept.record_length) == (4.6, 1.0)
    bare = FRFData(freq, np.ones(4))
    assert (bare.window_decay_rate, bare.record_length) == (None, None)
    dropped = one.with_measurement()                # the same lines, stating nothing
    assert (dropped.window_decay_rate, dropped.record_length) == (None, None)
    np.testing.assert_array_equal(dropped.values, one.values)
    assert dropped.excitation is one.excitation and dropped.quantity == "accelerance"
    assert bare.with_measurement(record_length=2.0).record_length == 2.0
    for name, bad in (("window_decay_rate", -1.0), ("record_length", 0.0),
                      ("record_length", np.inf)):
        with pytest.raises(ValueError, match=name):
            FRFData(freq, np.ones(4), **{name: bad})
    with pytest.warns(UserWarning, match=r"exponential window \(decay 4.6 1/s\)"):
        FRFSet.from_frfs([one, one])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        FRFSet.from_frfs([bare, bare])


def test_frf_data_carries_its_excitation_spectrum_and_checks_it():
    """``FRFData(excitation=...)``: the excitation's autospectrum per line (a hammer's force
    spectrum), read-only, kept by select, band and conversion; a wrong length or a
    negative value is refused, naming it."""
    freq = np.array([0.0, 1.0, 2.0, 3.0])
    one = FRFData(freq, [1.0, 1 + 1j, 2j, 3.0], quantity="accelerance",
                  excitation=[4.0, 3.0, 2.0, 1.0])
    assert not one.excitation.flags.writeable
    assert np.array_equal(one.band((1.0, 2.0)).excitation, [3.0, 2.0])
    with pytest.warns(UserWarning, match="dropped the 0 Hz line"):
        assert np.array_equal(one.to_receptance().excitation, [3.0, 2.0, 1.0])
    assert FRFData(freq, np.ones(4)).excitation is None
    with pytest.raises(ValueError, match="excitation must have the length of freq_hz"):
        FRFData(freq, np.ones(4), excitation=np.ones(3))
    with pytest.raises(ValueError, match="excitation must be non-negative.*-1.0"):
        FRFData(freq, np.ones(4), excitation=[1.0, -1.0, 1.0, 1.0])


def test_read_frf_set_reads_every_row_conjugated_or_negated_as_read_frf_does(tmp_path):
    """``conjugate``/``negate`` apply to every row, as :func:`read_frf` applies them to one
    FRF (the command line's --conjugate/--negate for a set); a flag that is not a bool is
    refused as read_frf refuses it."""
    paths = write_uffs(tmp_path, [(1, 1), (2, 1)])
    plain = read_frf_set(paths)
    turned = read_frf_set(paths, conjugate=True, negate=True)
    np.testing.assert_array_equal(turned.values, -np.conj(plain.values))
    assert turned.driving_point == plain.driving_point and turned.outputs == plain.outputs
    for i, path in enumerate(paths):
        np.testing.assert_array_equal(turned.values[i],
                                      read_frf(path, conjugate=True, negate=True).values)
    with pytest.raises(TypeError, match="negate must be True or False"):
        read_frf_set(paths, negate="yes")
