"""modalid.io: round trips through every format, the measured files, and refused inputs."""

import hashlib
import warnings
from pathlib import Path

import numpy as np
import pytest
import pyuff
import scipy.io
from scipy.signal import find_peaks

from modalid import FRFData, read_frf, write_frf
from modalid.io import describe_frfs, read_complex_lines, read_frfs

DATA = Path(__file__).parent / "data"
QUANTITIES = ("receptance", "mobility", "accelerance")
SHA256 = {
    "meas_point_1.txt": "ae99c87c17747ddc0819dffc6fadaf605385b5e5a0eec43415b724aaccf7223a",
    "meas_point_2.txt": "872f58a6e812cd9abed390262bec120d9064738524faff082929dd303a17e340",
    "meas_point_3.txt": "2c3a420cbb076fc88532fc625d642295e14cf3b79bcc73d26e759ab33f80b5f6",
    "case1.mat": "6982bf24ef3d7a4aea02615850c4ace0936ebd829f5644c140cb3e2e34ae9b86",
    "case2.mat": "1bc35fc10bd1688b78735525185a9a8044e23d01cabc55a60e6a8685e4be373b",
    # gzip of the publisher's file: the hash is of the bytes it decompresses to
    "acceleration.lvm.gz": "9f4d997c5aadd2835f62aeb8b3b06d8f67352ea525ba02d50f50be915585d167",
}


def make_frf(quantity="accelerance", coherence=True, freq_hz=None, seed=0):
    """Values spanning 15 decades, so relative precision is tested at every scale."""
    rng = np.random.default_rng(seed)
    f = np.arange(801) * 0.3125 if freq_hz is None else freq_hz
    scale = 10.0 ** rng.uniform(-12, 3, f.size)
    values = (rng.normal(size=f.size) + 1j * rng.normal(size=f.size)) * scale
    coh = rng.uniform(0, 1, f.size) if coherence else None
    return FRFData(f, values, quantity=quantity, coherence=coh)


def write_uff_sets(path, *dsets):
    uff = pyuff.UFF(str(path))
    with warnings.catch_warnings():  # pyuff leaves the file of a binary set unclosed
        warnings.simplefilter("ignore", ResourceWarning)
        for dset in dsets:
            uff.write_sets(dset, mode="add")
    return path


def header151():
    return pyuff.prepare_151(
        model_name="beam", description="none", db_app="modalid", date_db_created="01-Jan-25",
        time_db_created="00:00:00", version_db1=1, version_db2=1, file_type=0,
        date_db_saved="01-Jan-25", time_db_saved="00:00:00", program="modalid",
        date_db_written="01-Jan-25", time_db_written="00:00:00")


def dset58(values=None, freq=None, **fields):
    freq = np.arange(10.0) if freq is None else freq
    values = (np.arange(1, freq.size + 1) * (1 + 0.5j)) if values is None else values
    spec = dict(binary=0, func_type=4, rsp_node=1, rsp_dir=3, ref_node=1, ref_dir=3,
                abscissa_spacing=1, abscissa_spec_data_type=18, ordinate_spec_data_type=12,
                orddenom_spec_data_type=13)
    spec.update(fields)
    return pyuff.prepare_58(data=values, x=freq, **spec)


# --------------------------------------------------------------------- the data files
@pytest.mark.parametrize("name", sorted(SHA256))
def test_data_files_are_the_documented_bytes(name):
    raw = (DATA / name).read_bytes()
    if name.endswith(".gz"):
        import gzip

        raw = gzip.decompress(raw)
    assert hashlib.sha256(raw).hexdigest() == SHA256[name]


# ------------------------------------------------------------------------ round trips
EXACT = [("a.csv", {}), ("a.npz", {}), ("a.mat", {}), ("a.uff", {"binary": True}),
         ("a.unv", {"binary": True})]


@pytest.mark.parametrize("quantity", QUANTITIES)
@pytest.mark.parametrize("coherence", [True, False])
@pytest.mark.parametrize("name, options", EXACT)
def test_round_trip_is_bit_identical(tmp_path, quantity, coherence, name, options):
    # an irregular grid of arbitrary doubles: nothing may be rounded
    f = np.cumsum(np.random.default_rng(1).uniform(0.01, 1.0, 300))
    frf = make_frf(quantity, coherence, freq_hz=f)
    write_frf(tmp_path / name, frf, **options)
    back = read_frf(tmp_path / name)
    assert back.quantity == quantity
    np.testing.assert_array_equal(back.freq_hz, frf.freq_hz)
    np.testing.assert_array_equal(back.values, frf.values)
    if coherence:
        np.testing.assert_array_equal(back.coherence, frf.coherence)
    else:
        assert back.coherence is None


@pytest.mark.parametrize("name", ["a.csv", "a.npz", "a.mat"])
def test_the_excitation_spectrum_round_trips(tmp_path, name):
    """A one-hit hammer FRF carries its force spectrum (``excitation``): CSV, NPZ and MAT
    write it and read it back bit-exact, so that ``modalid fit`` on the file ends its
    automatic band where the hammer stopped reaching; a named column is found by its
    name (``force_spectrum``)."""
    frf = make_frf(coherence=False)
    one = FRFData(frf.freq_hz, frf.values, quantity=frf.quantity,
                  excitation=np.random.default_rng(2).uniform(0, 5, frf.freq_hz.size))
    write_frf(tmp_path / name, one)
    back = read_frf(tmp_path / name)
    np.testing.assert_array_equal(back.excitation, one.excitation)
    assert back.coherence is None
    text = tmp_path / "b.csv"
    text.write_text("freq_hz,real,imag,force_spectrum\n1.0,1.0,0.0,4.0\n2.0,0.5,0.5,3.0\n")
    assert read_frf(text, quantity="receptance").excitation.tolist() == [4.0, 3.0]
    text.write_text("freq_hz,real,imag,excitation\n1.0,1.0,0.0,4.0\n2.0,0.5,0.5,-3.0\n")
    with pytest.raises(ValueError, match="b.csv: excitation must be non-negative"):
        read_frf(text, quantity="receptance")


@pytest.mark.parametrize("name", ["a.csv", "a.npz", "a.mat"])
def test_how_the_frf_was_measured_round_trips(tmp_path, name):
    """The records' exponential window and length (``FRFData.window_decay_rate``,
    ``record_length``) are written and read back exactly by CSV (comment lines), NPZ and
    MAT (scalars), so that a fit of the file models them unasked; an FRF that states
    nothing writes nothing of them."""
    frf = make_frf()
    stated = FRFData(frf.freq_hz, frf.values, quantity=frf.quantity, coherence=frf.coherence,
                     window_decay_rate=4.605170185988091, record_length=1.0006)
    write_frf(tmp_path / name, stated)
    back = read_frf(tmp_path / name)
    assert (back.window_decay_rate, back.record_length) == (4.605170185988091, 1.0006)
    np.testing.assert_array_equal(back.values, frf.values)
    write_frf(tmp_path / f"bare_{name}", frf)
    back = read_frf(tmp_path / f"bare_{name}")
    assert (back.window_decay_rate, back.record_length) == (None, None)


def test_a_csv_states_how_it_was_measured_in_comments_and_a_uff_in_an_id_line(tmp_path):
    """A CSV's ``# record_length (s): T`` and ``# window_decay_rate: 2`` (the unit may be
    left out) are read; a wrong unit, a word for a number or a negative value is refused
    naming the file. A UFF dataset 58 keeps them in its ID line 4 (80 characters:
    exact where the shortest decimals fit, else to 12 digits), ASCII or binary."""
    path = tmp_path / "a.csv"
    table = "freq_hz,real,imag\n1.0,1.0,0.0\n2.0,0.5,0.5\n"
    path.write_text("# quantity: mobility\n# record_length (s): 2.5\n"
                    "#window_decay_rate = 2\n" + table)
    back = read_frf(path)
    assert (back.window_decay_rate, back.record_length) == (2.0, 2.5)
    for line in ("# record_length: 2.5 s", "# Record_length = 2.5 [s]", "# RECORD_LENGTH 2.5",
                 "# record_length: 2.5 # measured"):   # other programs' ways of writing it
        path.write_text(f"# quantity: mobility\n{line}\n{table}")
        assert read_frf(path).record_length == 2.5
    for line, error in (("# record_length (1/s): 2", "the record length is stated in s, "
                                                     "not '1/s'"),
                        ("# window_decay_rate (1/ms): 0.0092", "the window's decay rate is "
                                                              "stated in 1/s, not '1/ms'"),
                        ("# record_length [ms]: 1000", "stated in s, not 'ms'"),
                        ("# record_length: two", "the record length must be a number"),
                        ("# record_length (s): inf", "must be finite and > 0"),
                        ("# window_decay_rate: -1", "must be finite and >= 0 \\(1/s\\)"),
                        ("# record_length: 2 ms", "stated in s, not 'ms'"),
                        ("# window_decay_rate (1/s) 4.6 and more",
                         "write it as '# window_decay_rate \\(1/s\\)")):
        path.write_text(f"# quantity: mobility\n{line}\n{table}")
        with pytest.raises(ValueError, match=error) as raised:
            read_frf(path)
        assert str(raised.value).startswith(f"{path} says '{line}': ")
    for decay, length, binary in ((4.605170185988091, 1.0006000000000002, False),
                                  (4.605170185988091, 1.0006000000000002, True),
                                  (1.2345678901234567e-100, 1.2345678901234567e+100, False)):
        frf = FRFData([1.0, 2.0], [1.0, 0.5j], window_decay_rate=decay, record_length=length)
        write_frf(tmp_path / "a.uff", frf, binary=binary)
        back = read_frf(tmp_path / "a.uff")
        exact = length < 1e3
        assert back.window_decay_rate == (decay if exact else pytest.approx(decay, rel=1e-11))
        assert back.record_length == (length if exact else pytest.approx(length, rel=1e-11))
    write_frf(tmp_path / "bare.uff", FRFData([1.0, 2.0], [1.0, 0.5j]))
    assert read_frf(tmp_path / "bare.uff").record_length is None
    # another program's ID line 4: what does not read as a statement is left out, said
    import pyuff

    uff = pyuff.UFF(str(tmp_path / "bare.uff"))
    sets = uff.read_sets()
    sets = [sets] if isinstance(sets, dict) else sets
    sets[0]["id4"] = "record_length measured twice; window_decay_rate: 2"
    pyuff.UFF(str(tmp_path / "vendor.uff")).write_sets(sets, mode="add")
    with pytest.warns(UserWarning, match="ID line 4 says 'record_length measured twice': "
                                         "the record length must be a number"):
        back = read_frf(tmp_path / "vendor.uff")
    assert (back.window_decay_rate, back.record_length) == (2.0, None)


@pytest.mark.parametrize("quantity", QUANTITIES)
def test_ascii_uff_round_trip_to_the_formats_twelve_digits(tmp_path, quantity):
    frf = make_frf(quantity)
    write_frf(tmp_path / "a.uff", frf)
    assert b"58b" not in (tmp_path / "a.uff").read_bytes()  # ASCII, not binary
    back = read_frf(tmp_path / "a.uff")
    assert back.quantity == quantity
    np.testing.assert_array_equal(back.freq_hz, frf.freq_hz)  # f0 = 0, df = 0.3125 exact
    # E20.12: each part rounded to 12 significant digits
    np.testing.assert_allclose(back.values.real, frf.values.real, rtol=5e-12, atol=0)
    np.testing.assert_allclose(back.values.imag, frf.values.imag, rtol=5e-12, atol=0)
    np.testing.assert_allclose(back.coherence, frf.coherence, rtol=5e-12, atol=0)


def test_ascii_uff_refuses_a_grid_it_cannot_hold(tmp_path):
    frf = make_frf(freq_hz=np.linspace(1.0, 100.0, 500))  # df = 0.19839679...
    with pytest.raises(ValueError, match="binary=True"):
        write_frf(tmp_path / "a.uff", frf)
    write_frf(tmp_path / "a.uff", frf, binary=True)
    np.testing.assert_array_equal(read_frf(tmp_path / "a.uff").freq_hz, frf.freq_hz)


def test_uff_writes_the_dofs_and_quantity_codes(tmp_path):
    """DOFs and codes as given; directions of opposite sign store the FRF negated, so that
    it reads back as written (the reader takes every record along positive directions)."""
    frf = make_frf("mobility")
    write_frf(tmp_path / "a.uff", frf, response=(5, -2), reference=(7, 1), binary=True)
    row = describe_frfs(tmp_path / "a.uff").iloc[0]
    assert (row.response_node, row.response_dir, row.reference_node, row.reference_dir) == \
        (5, -2, 7, 1)
    assert row.negated and row.to_si == 1.0
    np.testing.assert_array_equal(read_frf(tmp_path / "a.uff").values, frf.values)
    np.testing.assert_array_equal(pyuff.UFF(str(tmp_path / "a.uff")).read_sets(0)["data"],
                                  -frf.values)
    assert row.quantity == "mobility" and row.coherence
    dsets = pyuff.UFF(str(tmp_path / "a.uff")).read_sets()
    assert [d["func_type"] for d in dsets] == [4, 6]  # FRF, then its coherence
    assert (dsets[0]["ordinate_spec_data_type"], dsets[0]["orddenom_spec_data_type"],
            dsets[0]["abscissa_spec_data_type"]) == (11, 13, 18)


def test_write_overwrites(tmp_path):
    for quantity in ("receptance", "accelerance"):
        write_frf(tmp_path / "a.uff", make_frf(quantity), binary=True)
        assert [f.quantity for f in read_frfs(tmp_path / "a.uff")] == [quantity]


# ------------------------------------------------------------------ the measured files
@pytest.mark.parametrize("point", [1, 2, 3])
def test_pyuff_beam_accelerance(point):
    path = DATA / f"meas_point_{point}.txt"
    frf = read_frf(path, format="complex-lines", freq_hz=np.arange(1001.0),
                   quantity="accelerance")
    assert len(frf) == 1001 and frf.freq_hz[0] == 0 and frf.freq_hz[-1] == 1000
    assert frf.quantity == "accelerance"
    # parsed without eval, and identical to numpy's own complex parser
    np.testing.assert_array_equal(frf.values, np.genfromtxt(path, dtype=complex))
    # the six beam modes: the only peaks a decade above their surroundings
    peaks, _ = find_peaks(np.log10(np.abs(frf.values)), prominence=1.0)
    np.testing.assert_array_equal(frf.freq_hz[peaks], [52, 142, 279, 460, 687, 959])
    # the .txt extension is recognised as complex lines; the helper agrees
    same = read_frf(path, freq_hz=np.arange(1001.0), quantity="accelerance")
    np.testing.assert_array_equal(same.values, frf.values)
    helper = read_complex_lines(path, freq_hz=np.arange(1001.0), quantity="accelerance")
    np.testing.assert_array_equal(helper.values, frf.values)


def test_complex_lines_need_frequencies_and_quantity():
    path = DATA / "meas_point_1.txt"
    with pytest.raises(ValueError, match="freq_hz="):
        read_frf(path, quantity="accelerance")
    with pytest.raises(ValueError, match="quantity="):
        read_frf(path, freq_hz=np.arange(1001.0))
    with pytest.raises(ValueError, match="1001 values but freq_hz has 1000"):
        read_frf(path, freq_hz=np.arange(1000.0), quantity="accelerance")


def test_complex_lines_are_never_evaluated(tmp_path):
    marker = tmp_path / "executed"
    path = tmp_path / "evil.txt"
    path.write_text(f"(1+2j)\n__import__('pathlib').Path({str(marker)!r}).touch()\n")
    with pytest.raises(ValueError, match="line 2 .* is not a complex number"):
        read_frf(path, format="complex-lines", freq_hz=[0.0, 1.0], quantity="receptance")
    assert not marker.exists()


def test_vtb_case1_analyzer_export():
    with pytest.warns(UserWarning, match=r"outside \[0, 1\] at 5 lines .*1.24622 at 0 Hz"):
        frf = read_frf(DATA / "case1.mat", quantity="accelerance")
    assert len(frf) == 1601 and frf.freq_hz[0] == 0 and frf.freq_hz[-1] == 500
    np.testing.assert_allclose(np.diff(frf.freq_hz), 0.3125)
    assert abs(frf.freq_hz[np.argmax(np.abs(frf.values))] - 212.2) < 0.5
    assert np.all((frf.coherence >= 0) & (frf.coherence <= 1))
    raw = scipy.io.loadmat(DATA / "case1.mat")
    np.testing.assert_array_equal(frf.values, raw["Hf_chan_2"].ravel())
    ok = raw["Hf_coh_chan_2"].ravel() <= 1  # only the 5 lines above 1 were changed
    np.testing.assert_array_equal(frf.coherence[ok], raw["Hf_coh_chan_2"].ravel()[ok])


def test_vtb_case2_analyzer_export():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        frf = read_frf(DATA / "case2.mat", quantity="mobility")
    assert len(frf) == 1601 and frf.quantity == "mobility"
    assert abs(frf.freq_hz[np.argmax(np.abs(frf.values))] - 192.5) < 0.5
    assert 0 <= frf.coherence.min() and frf.coherence.max() <= 1


def test_analyzer_export_needs_the_quantity():
    with pytest.raises(ValueError, match="does not say which quantity.*pass quantity="):
        read_frf(DATA / "case2.mat")


def test_analyzer_export_with_several_channels(tmp_path):
    f = np.arange(5.0)
    scipy.io.savemat(tmp_path / "a.mat", {"Freq_domain": f[:, None],
                                          "Hf_chan_2": (f + 1j)[:, None],
                                          "Hf_chan_3": (2 * f + 1j)[:, None]})
    with pytest.raises(ValueError, match="holds 2 FRFs: pass index="):
        read_frf(tmp_path / "a.mat", quantity="receptance")
    third = read_frf(tmp_path / "a.mat", quantity="receptance", index=1)
    np.testing.assert_array_equal(third.values, 2 * f + 1j)
    assert list(describe_frfs(tmp_path / "a.mat").response_channel) == [2, 3]


# ---------------------------------------------------------------------------- UFF input
@pytest.mark.parametrize("code, quantity", [(8, "receptance"), (11, "mobility"),
                                            (12, "accelerance")])
@pytest.mark.parametrize("binary", [0, 1])
def test_uff_quantity_from_the_ordinate_type(tmp_path, code, quantity, binary):
    path = write_uff_sets(tmp_path / "a.uff", dset58(ordinate_spec_data_type=code,
                                                     binary=binary))
    frf = read_frf(path)
    assert frf.quantity == quantity
    np.testing.assert_array_equal(frf.values, np.arange(1, 11) * (1 + 0.5j))
    with pytest.raises(ValueError, match=f"says its FRF is {quantity}"):
        read_frf(path, quantity=next(q for q in QUANTITIES if q != quantity))


def test_uff_without_a_stated_quantity(tmp_path):
    path = write_uff_sets(tmp_path / "a.uff", dset58(ordinate_spec_data_type=0,
                                                     orddenom_spec_data_type=0))
    with pytest.raises(ValueError, match="pass quantity="):
        read_frf(path)
    assert read_frf(path, quantity="mobility").quantity == "mobility"


def test_uff_refuses_other_functions_of_frequency(tmp_path):
    apparent_mass = write_uff_sets(tmp_path / "m.uff", dset58(ordinate_spec_data_type=13,
                                                              orddenom_spec_data_type=12))
    with pytest.raises(ValueError, match="specific data type 13 over 12"):
        read_frf(apparent_mass)
    time = write_uff_sets(tmp_path / "t.uff", dset58(abscissa_spec_data_type=17))
    with pytest.raises(ValueError, match="abscissa specific data type 17"):
        read_frf(time)
    response = write_uff_sets(tmp_path / "r.uff", dset58(func_type=1))
    with pytest.raises(ValueError, match="no FRF.*function types \\[1\\]"):
        read_frf(response)


def test_uff_refuses_an_frf_of_real_values(tmp_path):
    """A magnitude stored as real data is no FRF (it was read with a zero phase)."""
    path = write_uff_sets(tmp_path / "a.uff", dset58(values=np.arange(1.0, 11.0)))
    with pytest.raises(ValueError, match=r"holds real values \(ordinate data type 4\)"):
        read_frf(path)


def test_uff_abscissa_in_rad_per_s(tmp_path):
    path = write_uff_sets(tmp_path / "a.uff", dset58(freq=np.arange(10.0) * 2 * np.pi,
                                                     abscissa_spacing=0, binary=1,
                                                     abscissa_axis_units_lab="rad/s"))
    np.testing.assert_allclose(read_frf(path).freq_hz, np.arange(10.0), rtol=1e-15)


def test_uff_with_several_frfs(tmp_path):
    path = write_uff_sets(tmp_path / "a.uff", header151(),
                          dset58(ref_node=1), dset58(ref_node=2, values=np.ones(10) * 1j))
    # the message names each record's points (the CLI had said "see describe_frfs")
    with pytest.raises(ValueError, match=r"holds 2 FRFs \(0: response 1\+3, reference 1\+3; "
                                         r"1: response 1\+3, reference 2\+3\): pass index="):
        read_frf(path)
    frfs = read_frfs(path)
    assert len(frfs) == 2
    np.testing.assert_array_equal(read_frf(path, index=1).values, np.ones(10) * 1j)
    assert list(describe_frfs(path).reference_node) == [1, 2]
    with pytest.raises(ValueError, match="index must be below 2"):
        read_frf(path, index=2)


def units164(code, description, length, force):
    return pyuff.prepare_164(units_code=code, units_description=description, temp_mode=1,
                             length=length, force=force, temp=1.0, temp_offset=273.15)


def test_uff_values_taken_to_si_by_the_units_dataset_before_each_record(tmp_path):
    """Dataset 164 divides lengths and forces in file units by its factors: an inch-pound
    file's accelerance in in/s^2/lbf is x lbf/in in SI; a dataset 164 holds for the
    records after it (the first record here is before it: SI); stated exponents of the
    ordinate's records 9/10 are used, all-zero ones are taken as a length over a force."""
    inch, lbf = 1 / 0.0254, 1 / 4.4482216152605      # file units per m, per N
    values = np.arange(1, 11) * (1 + 0.5j)
    path = write_uff_sets(tmp_path / "a.uff", header151(), dset58(ref_node=9),
                          units164(7, "IN", inch, lbf), dset58(),
                          dset58(ref_node=2, ordinate_len_unit_exp=1,
                                 orddenom_force_unit_exp=1),
                          units164(5, "MM", 1000.0, 1000.0), dset58(ref_node=3),
                          units164(7, "IN", inch, lbf),
                          dset58(ref_node=4, ordinate_len_unit_exp=1,
                                 ordinate_force_unit_exp=-1))
    frfs = read_frfs(path)
    np.testing.assert_allclose(frfs[4].values, values * 0.0254 / 4.4482216152605, rtol=1e-12)
    to_si = 0.0254 / 4.4482216152605
    np.testing.assert_array_equal(frfs[0].values, values)
    np.testing.assert_allclose(frfs[1].values, values * to_si, rtol=1e-12)
    np.testing.assert_allclose(frfs[2].values, values * to_si, rtol=1e-12)
    np.testing.assert_allclose(frfs[3].values, values, rtol=1e-12)   # mm / mN = m / N
    np.testing.assert_allclose(describe_frfs(path).to_si, [1.0, to_si, to_si, 1.0, to_si],
                               rtol=1e-12)
    bad = write_uff_sets(tmp_path / "b.uff", units164(9, "user", 0.0, 1.0), dset58())
    with pytest.raises(ValueError, match=r"units dataset 164 number 1 \(user\) does not give "
                                         r"a positive length and force factor"):
        read_frf(bad)


@pytest.mark.parametrize("code, name, length, force", [
    (2, "BG", 3.28083989501312, 0.224808943099710),       # foot, pound-force
    (3, "MG", 1.0, 0.101971621297793),                     # metre, kilogram-force
    (8, "GM", 1000.0, 0.101971621297793)])                 # millimetre, kilogram-force
@pytest.mark.parametrize("code58, quantity", [(8, "receptance"), (11, "mobility"),
                                              (12, "accelerance")])
def test_uff_units_of_every_standard_system(tmp_path, code, name, length, force, code58,
                                            quantity):
    """A length over a force in file units is ``force / length`` of it in SI, whatever the
    quantity: 1 ft/lbf = 0.0685 m/N, 1 m/kgf = 0.102 m/N, 1 mm/kgf = 1.02e-4 m/N."""
    values = np.arange(1, 11) * (1 + 0.5j)
    path = write_uff_sets(tmp_path / "a.uff", units164(code, name, length, force),
                          dset58(ordinate_spec_data_type=code58))
    frf = read_frf(path)
    assert frf.quantity == quantity
    np.testing.assert_allclose(frf.values, values * force / length, rtol=1e-12)


def test_uff_units_datasets_read_from_the_text_and_checked(tmp_path):
    """A dataset 164 without its temperature lines (pyuff cannot parse it: the file had
    become unreadable) is read from the text; a dataset 164 after the records changes
    none of them; factors that are not their code's are warned about (read by the
    factors); exponents that are not a length over a force are refused outside SI."""
    inch, lbf = 1 / 0.0254, 1 / 4.4482216152605
    write_uff_sets(tmp_path / "a.uff", units164(7, "IN", inch, lbf), dset58())
    text = (tmp_path / "a.uff").read_text().splitlines(keepends=True)
    start = next(i for i, line in enumerate(text) if line.strip() == "164")
    # record 1, then the factors' line; the temperature offset's line dropped
    (tmp_path / "short.uff").write_text("".join(text[:start + 3] + text[start + 4:]))
    np.testing.assert_allclose(read_frf(tmp_path / "short.uff").values,
                               np.arange(1, 11) * (1 + 0.5j) * lbf / inch, rtol=1e-12)
    after = write_uff_sets(tmp_path / "after.uff", dset58(), units164(7, "IN", inch, lbf))
    np.testing.assert_array_equal(read_frf(after).values, np.arange(1, 11) * (1 + 0.5j))
    odd = write_uff_sets(tmp_path / "odd.uff", units164(1, "SI units", 3.28083989501312,
                                                        0.224808943099710), dset58())
    with pytest.warns(UserWarning, match=r"says code 1 \(SI: factors 1, 1\) but gives the "
                                         r"factors 3.28084, 0.224809: read by the factors"):
        read_frf(odd)
    ratio = write_uff_sets(tmp_path / "r.uff", units164(7, "IN", inch, lbf),
                           dset58(ordinate_len_unit_exp=1, ordinate_force_unit_exp=-1,
                                  orddenom_force_unit_exp=1))
    with pytest.raises(ValueError, match=r"records 9 and 10 state a length\^1 force\^-1 "
                                         r"over a length\^0 force\^1, not a length over a "
                                         r"force, in the units IN"):
        read_frf(ratio)
    si = write_uff_sets(tmp_path / "si.uff", dset58(ordinate_len_unit_exp=1,
                                                    ordinate_force_unit_exp=-1,
                                                    orddenom_force_unit_exp=1))
    np.testing.assert_array_equal(read_frf(si).values, np.arange(1, 11) * (1 + 0.5j))


def test_uff_axis_labels_that_contradict_its_units_are_warned_about(tmp_path):
    path = write_uff_sets(tmp_path / "a.uff", dset58(ordinate_axis_units_lab="g",
                                                     orddenom_axis_units_lab="N"))
    with pytest.warns(UserWarning, match=r"labels say 'g' over 'N' \(x9.80665 to SI\), "
                                         r"its units \(SI\) x1"):
        frf = read_frf(path)
    np.testing.assert_array_equal(frf.values, np.arange(1, 11) * (1 + 0.5j))
    agreeing = write_uff_sets(tmp_path / "b.uff", dset58(ordinate_axis_units_lab="m/s^2",
                                                         orddenom_axis_units_lab="N"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read_frf(agreeing)


@pytest.mark.parametrize("rsp_dir, ref_dir, sign", [(3, -3, -1), (-3, 3, -1), (-3, -3, 1),
                                                    (2, 2, 1)])
def test_uff_records_are_read_along_positive_directions(tmp_path, rsp_dir, ref_dir, sign):
    """A hammer hitting along -Z with the response along +Z stores minus the +Z/+Z FRF."""
    path = write_uff_sets(tmp_path / "a.uff", dset58(rsp_dir=rsp_dir, ref_dir=ref_dir))
    np.testing.assert_array_equal(read_frf(path).values, sign * np.arange(1, 11) * (1 + 0.5j))
    row = describe_frfs(path).iloc[0]
    assert (row.response_dir, row.reference_dir, row.negated) == (rsp_dir, ref_dir, sign < 0)


def test_uff_without_dataset_58(tmp_path):
    header = write_uff_sets(tmp_path / "h.uff", header151())
    with pytest.raises(ValueError, match=r"no dataset 58 .*types \[151\]"):
        read_frf(header)
    modes = write_uff_sets(tmp_path / "m.uff", pyuff.prepare_55(
        model_type=1, id1="NONE", id2="NONE", id3="NONE", id4="NONE", id5="NONE",
        analysis_type=2, data_ch=2, spec_data_type=8, data_type=2, r1=np.ones(3),
        r2=np.ones(3), r3=np.ones(3), n_data_per_node=3, node_nums=[1, 2, 3], load_case=1,
        mode_n=1, modal_m=0, freq=10.0, modal_damp_vis=0.0, modal_damp_his=0.0))
    with pytest.raises(ValueError, match=r"no dataset 58 .*types \[55\]"):
        read_frf(modes)


@pytest.mark.parametrize("binary", [False, True])
def test_truncated_uff(tmp_path, binary):
    write_frf(tmp_path / "a.uff", make_frf(), binary=binary)
    data = (tmp_path / "a.uff").read_bytes()
    for cut in (len(data) // 3, len(data) - 10):
        (tmp_path / "cut.uff").write_bytes(data[:cut])
        with pytest.raises(ValueError, match="truncated or corrupt"):
            read_frf(tmp_path / "cut.uff")


def test_corrupt_uff(tmp_path):
    write_frf(tmp_path / "a.uff", make_frf(coherence=False))
    lines = (tmp_path / "a.uff").read_text().splitlines(keepends=True)
    (tmp_path / "gap.uff").write_text("".join(lines[:20] + lines[25:]))  # 5 data lines lost
    with pytest.raises(ValueError, match="header says 801 values, the file holds 791"):
        read_frf(tmp_path / "gap.uff")
    lines[30] = lines[30][:25] + "x" + lines[30][26:]  # a number that does not parse
    (tmp_path / "bad.uff").write_text("".join(lines))
    with pytest.raises(ValueError, match="cannot read UFF file"):
        read_frf(tmp_path / "bad.uff")
    (tmp_path / "text.uff").write_text("freq_hz,real,imag\n0,1,2\n")
    with pytest.raises(ValueError, match="not a UFF file"):
        read_frf(tmp_path / "text.uff")


# ---------------------------------------------------------------------------- CSV input
def write_text(path, text):
    path.write_text(text)
    return path


@pytest.fixture
def reference_csv(tmp_path):
    frf = make_frf("accelerance", freq_hz=np.linspace(1.0, 50.0, 50))
    write_frf(tmp_path / "ref.csv", frf)
    return frf


def test_magnitude_phase_csv_equals_real_imag(tmp_path, reference_csv):
    f, h, coh = reference_csv.freq_hz, reference_csv.values, reference_csv.coherence
    layouts = {
        "Frequency [Hz],Magnitude,Phase [deg],Coherence": (f, np.abs(h), np.degrees(np.angle(h))),
        "freq_hz,mag_db,phase_rad,coh": (f, 20 * np.log10(np.abs(h)), np.angle(h)),
        "omega_rad_s,|H| (dB),Phase (°),gamma2": (2 * np.pi * f, 20 * np.log10(np.abs(h)),
                                                   np.degrees(np.angle(h))),
        "W (rad/s); H_real; H_imag; COH": (2 * np.pi * f, h.real, h.imag),
    }
    for i, (header, cols) in enumerate(layouts.items()):
        sep = ";" if ";" in header else ","
        rows = [sep.join(repr(float(v)) for v in row) for row in zip(*cols, coh)]
        path = write_text(tmp_path / f"{i}.csv", "\n".join([header] + rows) + "\n")
        frf = read_frf(path, quantity="accelerance")
        np.testing.assert_allclose(frf.freq_hz, f, rtol=1e-15)
        np.testing.assert_allclose(frf.values, h, rtol=1e-13)
        np.testing.assert_array_equal(frf.coherence, coh)


def test_csv_quantity_sources(tmp_path):
    body = "freq_hz,real,imag\n0,1,2\n1,3,4\n"
    plain = write_text(tmp_path / "plain.csv", body)
    with pytest.raises(ValueError, match="does not say which quantity.*pass quantity="):
        read_frf(plain)
    assert read_frf(plain, quantity="mobility").quantity == "mobility"
    commented = write_text(tmp_path / "c.csv", "# measured 2024\n# Quantity = Inertance\n" + body)
    assert read_frf(commented).quantity == "accelerance"
    with pytest.raises(ValueError, match="says its FRF is accelerance but quantity='mobility' "
                                         "was passed: drop the argument, or, if the file says "
                                         "it wrong, correct what it states"):
        read_frf(commented, quantity="mobility")
    named = write_text(tmp_path / "n.csv", "f,receptance_re,receptance_im\n0,1,2\n1,3,4\n")
    assert read_frf(named).quantity == "receptance"
    both = write_text(tmp_path / "b.csv", "# quantity: mobility\nf,receptance_re,receptance_im\n"
                      "0,1,2\n1,3,4\n")
    with pytest.raises(ValueError, match="several quantities"):
        read_frf(both)
    with pytest.raises(ValueError, match="quantity must be one of"):
        read_frf(plain, quantity="stiffness")


@pytest.mark.parametrize("header, quantity, scale", [
    ("f [kHz],re,im", None, 1.0),
    ("freq_hz,real [mm/N],imag [mm/N]", "receptance", 1e-3),
    ("freq (Hz),Re (um/N),Im (um/N)", "receptance", 1e-6),
    ("f [Hz],real [in/lbf],imag [in/lbf]", "receptance", 0.0254 / 4.4482216152605),
    ("f,real [(m/s)/N],imag [m/(N s)]", "mobility", 1.0),
    ("f,real [m/s^2/N],imag [m/s\u00b2/N]", "accelerance", 1.0),
    ("f,real [g/N],imag [g/N]", "accelerance", 9.80665),
    ("f,real [1/kg],imag [1/kg]", "accelerance", 1.0),
])
def test_csv_header_units_are_converted_and_state_the_quantity(tmp_path, header, quantity,
                                                                  scale):
    """A unit a header states is applied (kHz: the frequencies x 1000), and a value unit
    states the quantity; before, ``f [kHz]`` was read as Hz and ``[mm/N]`` as m/N."""
    khz = header.startswith("f [kHz]")
    rows = "\n".join(f"{f / 1000 if khz else f},{f * 2.0},{-f * 3.0}" for f in (10.0, 20.0))
    path = write_text(tmp_path / "u.csv", header + "\n" + rows + "\n")
    frf = read_frf(path, quantity=None if quantity else "mobility")
    assert frf.quantity == (quantity or "mobility")
    np.testing.assert_allclose(frf.freq_hz, [10.0, 20.0], rtol=1e-15)
    np.testing.assert_allclose(frf.values, np.array([20 - 30j, 40 - 60j]) * scale, rtol=1e-15)


def test_csv_units_stated_on_one_value_column_or_in_a_comment_are_refused(tmp_path):
    """``real [mm/N],imag``: the unit scaled the real part only (the FRF read as a transfer
    FRF); a ``# units:`` comment was ignored; a coherence in % without its unit was clipped
    to 1 at every line (the automatic band then trusted every line)."""
    rows = "10,1,2,99\n20,3,4,98\n"
    one = write_text(tmp_path / "one.csv", "f [Hz],real [mm/N],imag,coherence\n" + rows)
    with pytest.raises(ValueError, match=r"state different units \('real \[mm/N\]': mm/n, "
                                         r"'imag': none\)"):
        read_frf(one)
    same = write_text(tmp_path / "same.csv", "f,real [(m/s)/N],imag [m/(N s)]\n10,1,2\n20,3,4\n")
    np.testing.assert_array_equal(read_frf(same).values, [1 + 2j, 3 + 4j])
    comment = write_text(tmp_path / "c.csv", "# units: mm/N\nf [Hz],real,imag\n10,1,2\n")
    with pytest.raises(ValueError, match="'# units: mm/N': a unit comment is not read"):
        read_frf(comment, quantity="receptance")
    percent = write_text(tmp_path / "p.csv", "f [Hz],real [m/N],imag [m/N],coherence\n" + rows)
    with pytest.raises(ValueError, match=r"exceeds 1 at 2 of 2 lines .*coherence \[%\]"):
        read_frf(percent)
    stated = write_text(tmp_path / "s.csv", "f [Hz],real [m/N],imag [m/N],coherence [%]\n"
                        + rows)
    np.testing.assert_allclose(read_frf(stated).coherence, [0.99, 0.98])


@pytest.mark.parametrize("header", ["f,Re(H),Im(H)", "f,Real(FRF),Imag(FRF)",
                                    "f,real [-],imag [-]", "f,re,im,coherence (gamma^2)"])
def test_csv_brackets_that_name_no_unit_are_read_as_before(tmp_path, header):
    rows = "\n10,1,2" + (",0.5" if "coh" in header else "") + "\n20,3,4" + (
        ",0.6" if "coh" in header else "") + "\n"
    frf = read_frf(write_text(tmp_path / "b.csv", header + rows), quantity="receptance")
    np.testing.assert_array_equal(frf.values, [1 + 2j, 3 + 4j])


def test_csv_units_of_a_db_magnitude_and_of_a_set_are_read(tmp_path):
    """dB of mm/N: 0 dB is 1 mm/N (it was read as 1 m/N); a multi-FRF table's nested
    units (``[(m/s)/N]``, ``[m/(N s)]``) as a single FRF's."""
    db = write_text(tmp_path / "db.csv", "f [Hz],mag dB [mm/N],phase [deg]\n10,0,0\n20,20,90\n")
    frf = read_frf(db)
    assert frf.quantity == "receptance"
    np.testing.assert_allclose(frf.values, [1e-3, 1e-2j], atol=1e-18)
    # an analyzer's 0 Hz line at -inf dB is a zero magnitude (it refused the whole file);
    # +inf or nan still are not
    zero = write_text(tmp_path / "z.csv", "f [Hz],mag dB [mm/N],phase [deg]\n0,-inf,0\n10,0,0\n")
    np.testing.assert_array_equal(read_frf(zero).values, [0.0, 1e-3])
    bad = write_text(tmp_path / "b.csv", "f [Hz],mag dB [mm/N],phase [deg]\n0,inf,0\n10,0,0\n")
    with pytest.raises(ValueError, match="non-finite value at data row 1: inf"):
        read_frf(bad)
    from modalid.io_set import read_frf_set

    table = write_text(tmp_path / "set.csv", "f,p1 real [(m/s)/N],p1 imag [m/(N s)],p2 real "
                       "[(mm/s)/N],p2 imag [(mm/s)/N]\n10,1,2,3,4\n20,5,6,7,8\n")
    frfs = read_frf_set(table, driving_point=0)
    assert frfs.quantity == "mobility"
    np.testing.assert_allclose(frfs.values, [[1 + 2j, 5 + 6j], [3e-3 + 4e-3j, 7e-3 + 8e-3j]])


def test_csv_header_units_not_known_are_refused(tmp_path):
    body = "\n10,1,2\n20,3,4\n"
    for header, match in (("f [rpm],re,im", "'f \\[rpm\\]'.*must be in Hz, kHz or rad/s"),
                          ("omega [deg/s],re,im", "'omega \\[deg/s\\]'.*'deg/s'"),
                          ("f,re [V/N],im [V/N]", "'re \\[V/N\\]'.*'v/n'.*m/N, mm/N"),
                          ("f,re [dB re 1 m/N],im", "'re \\[dB re 1 m/N\\]'")):
        with pytest.raises(ValueError, match=match):
            read_frf(write_text(tmp_path / "x.csv", header + body), quantity="receptance")
    clash = write_text(tmp_path / "c.csv", "# quantity: accelerance\nf,re [mm/N],im [mm/N]" + body)
    with pytest.raises(ValueError, match="several quantities"):
        read_frf(clash)
    coh = write_text(tmp_path / "coh.csv", "f,re,im,coh [%]\n10,1,2,90\n20,3,4,50\n")
    np.testing.assert_allclose(read_frf(coh, quantity="receptance").coherence, [0.9, 0.5])


def test_csv_bad_data(tmp_path):
    cases = {
        "freq_hz,real,imag\n0,1,2\n1,nan,4\n": "column 'real' .* data row 2",
        "freq_hz,real,imag\n0,1,2\n1,,4\n": "column 'real' .* data row 2",
        "freq_hz,real,imag\n0,1,2\n1,3,oops\n": "column 'imag' .*'oops'",
        "freq_hz,real,imag\n1,1,2\n0,3,4\n": "strictly increasing",
        "freq_hz,real,imag,coherence\n0,1,2,0.5\n1,3,4,-2\n": r"outside \[0, 1\]",
        "freq_hz,magnitude,phase\n0,1,2\n1,3,4\n": "phase_deg or phase_rad",
        "freq_hz,x,y\n0,1,2\n1,3,4\n": "no real/imag pair.*accepted names",
        "time,real,imag\n0,1,2\n1,3,4\n": "exactly one frequency column",
        "f,omega,real,imag\n0,0,1,2\n1,6.3,3,4\n": "exactly one frequency column",
        "f,re,real,imag\n0,0,1,2\n1,6.3,3,4\n": "two real columns",
        "# quantity: stiffness\nf,re,im\n0,0,1\n1,1,1\n": "quantity must be one of",
    }
    for i, (text, message) in enumerate(cases.items()):
        path = write_text(tmp_path / f"{i}.csv", text)
        if "-2" in text:
            with pytest.warns(UserWarning, match=message):
                read_frf(path, quantity="receptance")
            continue
        with pytest.raises(ValueError, match=message):
            read_frf(path, quantity="receptance")


def test_csv_columns_override_and_separators(tmp_path):
    path = write_text(tmp_path / "a.csv", "x,Re,Im,f_hz\n1,2,3,10\n2,4,5,20\n")
    frf = read_frf(path, quantity="receptance", columns={"freq_hz": "X"})
    np.testing.assert_array_equal(frf.freq_hz, [1, 2])
    np.testing.assert_array_equal(frf.values, [2 + 3j, 4 + 5j])
    with pytest.raises(ValueError, match=r"columns\['real'\] = 'nope' is not in"):
        read_frf(path, quantity="receptance", columns={"real": "nope"})
    with pytest.raises(ValueError, match="columns key must be one of"):
        read_frf(path, quantity="receptance", columns={"frequency": "x"})
    data = np.array([[1.0, 2, 3], [2, 4, 5]])
    np.savetxt(tmp_path / "s.csv", data, delimiter=",", header="freq_hz,real,imag",
               comments="# quantity: receptance\n# ")  # the header on a comment line
    frf = read_frf(tmp_path / "s.csv")
    assert frf.quantity == "receptance"
    np.testing.assert_array_equal(frf.values, [2 + 3j, 4 + 5j])
    table = write_text(tmp_path / "a.txt", "# quantity: mobility\nf re im\n1 2 3\n2 4 5\n")
    frf = read_frf(table)
    assert frf.quantity == "mobility"
    np.testing.assert_array_equal(frf.values, [2 + 3j, 4 + 5j])


# ---------------------------------------------------------------------- NPZ / MAT input
def test_npz_and_mat_bad_data(tmp_path):
    f, h = np.arange(4.0), np.ones(4, complex)
    np.savez(tmp_path / "short.npz", freq_hz=f, values=h[:3], quantity="receptance")
    with pytest.raises(ValueError, match="freq_hz and values .* differ in length: 4 and 3"):
        read_frf(tmp_path / "short.npz")
    np.savez(tmp_path / "nan.npz", freq_hz=f, values=np.where(f == 2, np.nan, h))
    with pytest.raises(ValueError, match="values of .* holds .*nan.* at index 2"):
        read_frf(tmp_path / "nan.npz", quantity="receptance")
    np.savez(tmp_path / "q.npz", freq_hz=f, values=h, quantity="mobility")
    with pytest.raises(ValueError, match="says its FRF is mobility"):
        read_frf(tmp_path / "q.npz", quantity="receptance")
    np.savez(tmp_path / "cf.npz", freq_hz=f + 1j, values=h, quantity="receptance")
    with pytest.raises(ValueError, match="freq_hz of .*cf.npz must be real, got complex"):
        read_frf(tmp_path / "cf.npz")               # its imaginary part was dropped
    np.savez(tmp_path / "mag.npz", freq_hz=f, values=np.abs(h), quantity="receptance")
    with pytest.raises(ValueError, match="values of .*mag.npz is real, not complex"):
        read_frf(tmp_path / "mag.npz")              # a magnitude read with a zero phase
    np.savez(tmp_path / "other.npz", t=f, y=h)
    with pytest.raises(ValueError, match=r"one frequency and one values .*\['t', 'y'\]"):
        read_frf(tmp_path / "other.npz", quantity="receptance")
    scipy.io.savemat(tmp_path / "named.mat", {"w": 2 * np.pi * f, "Hxy": h, "c": f / 4})
    frf = read_frf(tmp_path / "named.mat", quantity="receptance",
                   columns={"omega_rad_s": "w", "values": "Hxy", "coherence": "c"})
    np.testing.assert_allclose(frf.freq_hz, f, rtol=1e-15)
    np.testing.assert_array_equal(frf.coherence, f / 4)
    scipy.io.savemat(tmp_path / "matrix.mat", {"freq_hz": f, "values": np.ones((4, 2))})
    with pytest.raises(ValueError, match=r"values of .* must be a vector, got shape \(4, 2\)"):
        read_frf(tmp_path / "matrix.mat", quantity="receptance")
    (tmp_path / "junk.mat").write_bytes(b"not a mat file" * 20)
    with pytest.raises(ValueError, match="junk.mat is a text file, not a MATLAB file"):
        read_frf(tmp_path / "junk.mat", quantity="receptance")
    (tmp_path / "binary.mat").write_bytes(b"\x00\x01not a mat file" * 20)
    with pytest.raises(ValueError, match="binary.mat is not a readable MATLAB file"):
        read_frf(tmp_path / "binary.mat", quantity="receptance")


def test_damaged_and_misnamed_files_are_refused_naming_them(tmp_path):
    """What a bad-input sweep found leaking library errors: a truncated .npz (an
    interrupted copy: zipfile's BadZipFile), a text file named .npz (refused as "pickled
    data"), a pickle named .mat (IndexError inside scipy), a binary file named .csv."""
    f, h = np.arange(1.0, 200.0), np.ones(199, complex)
    np.savez(tmp_path / "good.npz", freq_hz=f, values=h, quantity="receptance")
    (tmp_path / "cut.npz").write_bytes((tmp_path / "good.npz").read_bytes()[:3000])
    with pytest.raises(ValueError, match=r"cut.npz is not a readable .npz archive \(truncated"):
        read_frf(tmp_path / "cut.npz")
    (tmp_path / "text.npz").write_text("hello\n")
    with pytest.raises(ValueError, match="text.npz is not an .npz archive .it starts 'hello'"):
        read_frf(tmp_path / "text.npz")
    (tmp_path / "pickle.mat").write_bytes(b"\x80\x04K\x01.")
    with pytest.raises(ValueError, match="pickle.mat is not a readable MATLAB file"):
        read_frf(tmp_path / "pickle.mat", quantity="receptance")
    (tmp_path / "binary.csv").write_bytes(b"freq\x00\x01\x02" * 10)
    with pytest.raises(ValueError, match="binary.csv is a binary file, not a text table"):
        read_frf(tmp_path / "binary.csv")
    (tmp_path / "u16.csv").write_bytes("f,real,imag\n1,2,3\n".encode("utf-16"))
    with pytest.raises(ValueError, match="u16.csv is UTF-16 text .* save it as UTF-8"):
        read_frf(tmp_path / "u16.csv")
    (tmp_path / "empty.npz").write_bytes(b"")
    with pytest.raises(ValueError, match=r"empty.npz is not an .npz archive \(it is empty"):
        read_frf(tmp_path / "empty.npz")
    np.save(tmp_path / "one.npy", f)
    (tmp_path / "one.npz").write_bytes((tmp_path / "one.npy").read_bytes())
    with pytest.raises(ValueError, match="one.npz as .npz: it holds a single .npy array"):
        read_frf(tmp_path / "one.npz")


def test_a_windows_1252_table_is_read_with_its_units(tmp_path):
    """An analyzer's Windows export writes ``µm/N`` as the byte 0xB5 (not UTF-8): read as
    Windows-1252, the unit is honoured as in a UTF-8 file (it raised UnicodeDecodeError
    with no file name)."""
    text = "freq [Hz],real [\u00b5m/N],imag [\u00b5m/N]\n1,2,0\n2,4,-1\n"
    (tmp_path / "cp1252.csv").write_bytes(text.encode("cp1252"))
    (tmp_path / "utf8.csv").write_bytes(text.encode("utf-8"))
    windows, utf8 = read_frf(tmp_path / "cp1252.csv"), read_frf(tmp_path / "utf8.csv")
    np.testing.assert_array_equal(windows.values, [2e-6, 4e-6 - 1e-6j])
    np.testing.assert_array_equal(windows.values, utf8.values)


def test_model_json_without_fields_or_nested_too_deep_is_refused(tmp_path):
    """A JSON holding only the format line was read as an empty model (a rigid wall that
    ``impactpred predict`` then hit, "ok"); a deeply nested one raised RecursionError."""
    from modalid import ModalModel

    (tmp_path / "bare.json").write_text('{"format": "modalid.ModalModel"}')
    with pytest.raises(ValueError, match="bare.json.*holds none of the model's fields"):
        ModalModel.from_json(tmp_path / "bare.json")
    (tmp_path / "deep.json").write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(ValueError, match="deep.json is not JSON: RecursionError"):
        ModalModel.from_json(tmp_path / "deep.json")
    model = ModalModel.from_json('{"format": "modalid.ModalModel", "inverse_mass": 2.0}')
    assert model.inverse_mass == 2.0                      # a partial model is still read
    from modalid import MultiOutputModalModel              # the twin reader alike

    with pytest.raises(ValueError, match="holds none of the model's fields"):
        MultiOutputModalModel.from_json('{"format": "modalid.MultiOutputModalModel", '
                                        '"outputs": ["a"], "residues": []}')
    with pytest.raises(FileNotFoundError, match="no such file"):
        MultiOutputModalModel.from_json(tmp_path / "missing.json")


class _Payload:
    """Unpickling this object would create the file ``_Payload.target``."""

    target = None

    def __reduce__(self):
        return (Path.touch, (Path(_Payload.target),))


def test_npz_never_unpickles(tmp_path):
    _Payload.target = str(tmp_path / "executed")
    np.savez(tmp_path / "evil.npz", freq_hz=np.arange(2.0), values=np.ones(2, complex),
             quantity=np.array([_Payload()], dtype=object))
    with pytest.raises(ValueError, match="pickled/object arrays are refused"):
        read_frf(tmp_path / "evil.npz")
    assert not (tmp_path / "executed").exists()


# ------------------------------------------------------------------------- the API edges
def test_format_and_argument_errors(tmp_path):
    frf = make_frf()
    with pytest.raises(ValueError, match=r"'\.xlsx'.*'\.csv'.*'\.npz'.*'\.mat'.*'\.uff'"):
        write_frf(tmp_path / "a.xlsx", frf)
    with pytest.raises(ValueError, match=r"extension '\.xlsx'"):
        read_frf(tmp_path / "a.xlsx")
    with pytest.raises(ValueError, match="format must be one of"):
        write_frf(tmp_path / "a.csv", frf, format="hdf5")
    write_frf(tmp_path / "a.dat", frf, format="NPZ")  # the format argument beats the name
    np.testing.assert_array_equal(read_frf(tmp_path / "a.dat", format="npz").values, frf.values)
    with pytest.raises(TypeError, match="frf must be an FRFData"):
        write_frf(tmp_path / "a.csv", frf.values)
    with pytest.raises(TypeError, match="path must be a str"):
        read_frf(3)
    with pytest.raises(ValueError, match="apply to UFF files"):
        write_frf(tmp_path / "a.csv", frf, binary=True)
    with pytest.raises(ValueError, match="response direction must lie in -6..6"):
        write_frf(tmp_path / "a.uff", frf, response=(1, 7))
    with pytest.raises(ValueError, match="freq_hz= applies to format='complex-lines' only"):
        read_frf(tmp_path / "a.dat", format="npz", freq_hz=[0, 1])
    with pytest.raises(ValueError, match="columns= applies to CSV, NPZ and MAT"):
        read_frf(DATA / "case1.mat", format="uff", columns={"values": "x"})
    with pytest.raises(FileNotFoundError):
        read_frf(tmp_path / "missing.csv")


# ------------------------------------------------------------------- the sign convention
def rod_frf(quantity, noise=0.01):
    """A fixed rod's driving point (8 modes in band, 1 % noise)."""
    from data_synth import Rod, lightly_damped, synthetic_frf

    truth = lightly_damped(Rod(1.0, 1.0, support="fixed"), 12, 0.01)
    top = truth.modes["omega_n"].to_numpy()[8] / (2 * np.pi)
    return synthetic_frf(truth, np.linspace(0.02, top, 1500), quantity=quantity,
                         noise=noise, seed=1)


@pytest.mark.parametrize("quantity", QUANTITIES)
def test_check_sign_tells_a_conjugated_and_a_reversed_driving_point(quantity):
    from modalid.io import check_sign

    frf = rod_frf(quantity)
    found = {}
    for kind, values in (("as measured", frf.values), ("conjugate", frf.values.conj()),
                         ("reversed", -frf.values)):
        found[kind] = check_sign(FRFData(frf.freq_hz, values, quantity=quantity))
    assert [c.verdict for c in found.values()] == ["ok", "conjugate", "reversed"]
    assert found["as measured"].turning < -0.99 and found["as measured"].conductance > 0.99
    assert found["conjugate"].turning > 0.99
    assert found["reversed"].turning < -0.99 and found["reversed"].conductance < -0.99


def test_check_sign_leaves_the_measured_files_alone():
    """The analyzer exports (transfer FRFs of unknown sign) and pyuff's beam accelerances:
    none is taken for a conjugated or reversed driving point."""
    from modalid.io import check_sign

    frfs = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # coherence clipped at a few lines
        for name in ("case1.mat", "case2.mat"):
            frfs.append(read_frf(DATA / name, quantity="accelerance"))
    for point in (1, 2, 3):
        frfs.append(read_frf(DATA / f"meas_point_{point}.txt", format="complex-lines",
                             freq_hz=np.arange(1001.0), quantity="accelerance"))
    assert [check_sign(frf).verdict for frf in frfs] == ["ok"] * 5


def test_read_frf_conjugates_or_negates_on_request(tmp_path):
    frf = make_frf()
    write_frf(tmp_path / "a.csv", frf)
    np.testing.assert_array_equal(read_frf(tmp_path / "a.csv", conjugate=True).values,
                                  frf.values.conj())
    both = read_frf(tmp_path / "a.csv", conjugate=True, negate=True)
    np.testing.assert_array_equal(both.values, -frf.values.conj())
    np.testing.assert_array_equal(both.coherence, frf.coherence)
    with pytest.raises(TypeError, match="^negate must be True or False, got 'yes'$"):
        read_frf(tmp_path / "a.csv", negate="yes")


def test_a_check_sign_problem_names_the_file_and_the_option():
    from modalid.io import check_sign

    frf = rod_frf("receptance")
    reversed_ = check_sign(FRFData(frf.freq_hz, -frf.values))
    assert reversed_.problem("rod.csv") == (
        f"rod.csv: the real part of its mobility is negative (conductance score "
        f"{reversed_.conductance:+.2f}; a passive driving point's is positive, +1): its sign "
        "is reversed (response recorded against the force); read it with "
        "read_options={'negate': True}; if its quantity is stated wrong (an accelerance "
        "read as a receptance looks reversed too), read it with quantity=... (or correct "
        "the quantity the file states); if it is a transfer FRF, give the driving point's")
    assert check_sign(frf).problem("rod.csv") == ""


def test_a_text_file_named_mat_is_refused_on_one_line(tmp_path):
    path = tmp_path / "export.mat"
    path.write_text("freq_hz,real,imag\n1,2,3\n2,4,5\n")
    with pytest.raises(ValueError) as info:
        read_frf(path, quantity="receptance")
    assert str(info.value) == (f"{path} is a text file, not a MATLAB file (it starts "
                               "'freq_hz,real,imag'): rename it .csv or .txt, or pass "
                               "format='csv'")
    assert read_frf(path, quantity="receptance", format="csv").values[0] == 2 + 3j


# ------------------------------------------------------------------- model JSON files
def test_model_json_errors_name_the_file(tmp_path):
    from modalid import ModalModel

    empty = tmp_path / "empty.json"
    empty.write_text("")
    prose = tmp_path / "prose.json"
    prose.write_text("hello world\n")
    with pytest.raises(ValueError, match=f"^{empty} is empty: not a model JSON file$"):
        ModalModel.from_json(empty)
    with pytest.raises(ValueError, match=f"^{prose} is not JSON: Expecting value: line 1 "
                                         "column 1 \\(char 0\\)$"):
        ModalModel.from_json(prose)
    with pytest.raises(ValueError, match="^not a model JSON text \\(it does not start with "
                                         "'{'\\) nor a file name: 'hello world\\\\n'$"):
        ModalModel.from_json("hello world\n")
    with pytest.raises(FileNotFoundError, match="^no such file: 'missing.json'$"):
        ModalModel.from_json("missing.json")


def test_model_json_units_are_converted_or_refused(tmp_path):
    """A model stating mm/N is read in m/N (every receptance term divided by 1000);
    an unknown unit or poles not in rad/s are refused naming the file."""
    import json

    from modalid import ModalModel

    model = ModalModel(poles=[-0.3 + 7j], residues=[-0.2j], real_poles=[-12.0],
                       real_residues=[0.4], inverse_mass=0.25, flexibility=2e-3)
    payload = json.loads(model.to_json())
    payload["units"] = {"s": "rad/s", "receptance": "mm/N"}
    path = tmp_path / "mm.json"
    path.write_text(json.dumps(payload))
    read = ModalModel.from_json(path)
    assert read == ModalModel(poles=[-0.3 + 7j], residues=[-0.2e-3j], real_poles=[-12.0],
                              real_residues=[0.4e-3], inverse_mass=0.25e-3,
                              flexibility=2e-6)
    assert ModalModel.from_json(read.to_json()) == read        # written back in m/N
    for units, message in (
            ({"receptance": "furlong/N"}, f"units.receptance 'furlong/N' \\({path}\\) is not "
                                          "a known receptance unit: use one of m/N, mm/N"),
            ({"s": "Hz"}, f"units.s 'Hz' \\({path}\\) is not supported: poles must be in "
                          "rad/s"),
            ({"mobility": "m/s/N"}, f"the 'units' field \\({path}\\) names \\['mobility'\\]")):
        path.write_text(json.dumps(dict(payload, units=units)))
        with pytest.raises(ValueError, match="^" + message):
            ModalModel.from_json(path)


def test_a_single_npy_array_is_pointed_to_the_hammer_route(tmp_path):
    """A hammer test's records saved as one .npy array (rows time, force, response) are
    no FRF file: by extension or read as .npz, the error names frf_from_hammer."""
    path = tmp_path / "hit1.npy"
    np.save(path, np.zeros((3, 64)))
    for options in ({}, {"format": "npz"}):
        with pytest.raises(ValueError, match="hammer test's records .* with "
                                             "modalid.frf_from_hammer$"):
            read_frf(path, **options)


def test_a_bare_complex_lines_file_asks_for_all_it_lacks_at_once(tmp_path):
    """One complex value per line (no frequencies, no quantity): the error asks for the
    lines' frequencies and the quantity together (it asked for the quantity only once the
    frequencies were given); with the quantity given, for the frequencies alone."""
    path = tmp_path / "point.txt"
    path.write_text("(1+2j)\n(0.5-1j)\n(0.1+0.3j)\n")
    with pytest.raises(ValueError, match=r"holds bare complex values: pass freq_hz= \(Hz, one "
                                         r"per value line\), and quantity= one of"):
        read_frf(path, format="complex-lines")
    with pytest.raises(ValueError, match=r"one per value line\)$"):
        read_frf(path, format="complex-lines", quantity="accelerance")
