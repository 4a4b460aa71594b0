"""LabVIEW measurement files (modalid._lvm): the tutorial's real record and written ones
with two segments, comma separators and a point decimal; bad files refused by name."""

import gzip

import numpy as np
import pytest

from modalid._lvm import STANDARD_GRAVITY, read_lvm
from modalid._hammer_files import read_hammer_records

from pathlib import Path

DATA = Path(__file__).parent / "data"

FILE_HEADER = """LabVIEW Measurement{s}
Writer_Version{s}2
Separator{s}{sep_word}
Decimal_Separator{s}{dec}
Multi_Headings{s}Yes
X_Columns{s}No
***End_of_Header***{s}
"""
SEGMENT = """Channels{s}2{s}
Samples{s}{n}{s}{n}
Y_Unit_Label{s}N{s}g
X0{s}0{dec}0{s}0{dec}0
Delta_X{s}1{dec}000000E-3{s}1{dec}000000E-3
***End_of_Header***{s}
X_Value{s}Force{s}Acc{s}Comment
"""


def write_lvm(path, segments, *, sep="\t", dec=","):
    """An .lvm of ``segments`` (each an (n, 2) array: force, acceleration in g)."""
    s, word = sep, {"\t": "Tab", ",": "Comma"}[sep]
    text = FILE_HEADER.format(s=s, sep_word=word, dec=dec)
    for rows in segments:
        text += SEGMENT.format(s=s, n=len(rows), dec=dec)
        for f, a in rows:
            text += f"{s}{repr(float(f)).replace('.', dec)}{s}{repr(float(a)).replace('.', dec)}\n"
    path.write_text(text)
    return path


def test_the_tutorials_record_is_read_in_si_units():
    """ladisk's one hit: 50 030 samples at 50 kHz, the acceleration in g scaled by the
    standard gravity, the force in newtons as written, the time from Delta_X."""
    channels, units = read_lvm(DATA / "acceleration.lvm.gz")
    assert list(channels) == ["time", "Acceleration (Trigger)", "Force (Trigger)"]
    assert channels["time"][1] == pytest.approx(2e-5) and channels["time"].size == 50030
    assert units == {"Acceleration (Trigger)": ("g", STANDARD_GRAVITY),
                     "Force (Trigger)": ("Newtons", 1.0)}
    # the first row as written: -0,007387 g and 0,232147 N
    assert channels["Acceleration (Trigger)"][0] == pytest.approx(-0.007387 * 9.80665)
    assert channels["Force (Trigger)"][0] == 0.232147
    assert channels["Force (Trigger)"].max() == pytest.approx(195.6, abs=0.1)


@pytest.mark.parametrize("sep, dec", [("\t", ","), (",", ".")])
def test_two_segments_are_two_hits(tmp_path, sep, dec):
    rng = np.random.default_rng(0)
    hits = [rng.normal(size=(40, 2)) for _ in range(2)]
    path = write_lvm(tmp_path / "two.lvm", hits, sep=sep, dec=dec)
    channels, _ = read_lvm(path)
    np.testing.assert_array_equal(channels["Force"], [h[:, 0] for h in hits])
    np.testing.assert_allclose(channels["Acc"], [h[:, 1] * STANDARD_GRAVITY for h in hits])
    gz = tmp_path / "two.lvm.gz"
    gz.write_bytes(gzip.compress(path.read_bytes()))
    records = read_hammer_records([gz])
    assert records.force.shape == (2, 40) and records.fs == pytest.approx(1000.0)
    assert records.channels == ("time time, force Force, response Acc (x 9.80665: g to SI)")


# each a well-formed file edited into a bad one: (text replaced, by, the error's words)
BAD_EDITS = [
    ("\t1,0\t1,0\n", "\tone\t1,0\n", "row 1 of segment 1 does not hold 2 numbers"),
    ("\t1,0\t1,0\n", "\tNaN\t1,0\n", "row 1 of segment 1 holds a value that is not finite"),
    ("Samples\t3\t3", "Samples\t500\t500", "segment 1 holds 3 rows, its header says 500"),
    ("\t1,0\t1,0\n\t1,0\t1,0\n\t1,0\t1,0\n",
     "\t1,0\t1,0\n\t1,0\t1,0\n\t1,0\t1,0\nComment\tthe end\n\t1,0\t1,0\n",
     "segment 1 ends at a line that is not samples"),
    ("X_Value\tForce\tAcc", "X_Value\tForce\tForce", "repeat, or one is 'time'"),
    ("X_Columns\tNo", "X_Columns\tMulti", "has an X column per channel"),
]


@pytest.mark.parametrize("old, new, message", BAD_EDITS)
def test_bad_files_are_refused_naming_them(tmp_path, old, new, message):
    path = write_lvm(tmp_path / "bad.lvm", [np.ones((3, 2))])
    assert old in path.read_text()
    path.write_text(path.read_text().replace(old, new, 1))
    with pytest.raises(ValueError, match=f"bad.lvm.*{message}"):
        read_lvm(path)


def test_files_that_are_no_measurement_are_refused_naming_them(tmp_path):
    plain = tmp_path / "plain.lvm"
    plain.write_text("1\t2\n3\t4\n")
    with pytest.raises(ValueError, match="plain.lvm is not a LabVIEW measurement file"):
        read_lvm(plain)
    two = write_lvm(tmp_path / "two.lvm", [np.ones((3, 2)), np.ones((4, 2))])
    with pytest.raises(ValueError, match="two.lvm: segment 2 holds .* one test per file"):
        read_lvm(two)
    fake = tmp_path / "fake.lvm.gz"
    fake.write_text("not gzip")
    with pytest.raises(ValueError, match="fake.lvm.gz is not a readable gzip file"):
        read_lvm(fake)


def test_a_table_with_no_samples_is_refused_naming_it(tmp_path):
    """A CSV with its header and no rows raised IndexError in ``modalid hammer``."""
    for rows, n in (("", 0), ("0,1,2\n", 1)):
        path = tmp_path / f"rows{n}.csv"
        path.write_text("time,force,acceleration\n" + rows)
        with pytest.raises(ValueError, match=rf"rows{n}.csv: its channels hold {n} samples; "
                                             "a hammer record needs at least 8"):
            read_hammer_records([path])


def test_a_windows_1252_hammer_table_is_read(tmp_path):
    """``m/s²`` in a Windows export's header: "cannot parse ... 'utf-8' codec" before."""
    path = tmp_path / "hit.csv"
    rows = "".join(f"{k / 1000},{float(k == 2)},{np.sin(k / 20)}\n" for k in range(64))
    path.write_bytes(("time,force,acceleration [m/s\u00b2]\n" + rows).encode("cp1252"))
    records = read_hammer_records([path])
    assert records.force.shape == (1, 64)


def test_bare_rows_of_several_hits_rounded_intervals_and_unknown_units(tmp_path):
    """Multi_Headings No: the second hit follows as bare rows, ``Samples`` of them, and is
    a hit of its own; a Delta_X written with three digits is warned about and ``--fs``
    replaces the time it gives; a channel in volts is refused (it was kept unscaled: an
    FRF in V/N written as m/s^2/N) unless its scale to SI is given."""
    rng = np.random.default_rng(1)
    hits = [rng.normal(size=(20, 2)) for _ in range(2)]
    path = write_lvm(tmp_path / "bare.lvm", [np.vstack(hits)])
    text = path.read_text().replace("Samples\t40\t40", "Samples\t20\t20")
    path.write_text(text.replace("Y_Unit_Label\tN\tg", "Y_Unit_Label\tN\tV"))
    channels, units = read_lvm(path)
    np.testing.assert_array_equal(channels["Force"], [h[:, 0] for h in hits])
    assert units["Acc"] == ("V", None) and channels["time"].size == 20
    with pytest.raises(ValueError, match=r"response channel 'Acc' is in 'V', a unit not "
                                         r"known here .*--response-scale"):
        read_hammer_records([path])
    records = read_hammer_records([path], response_scale=2.0)
    assert records.force.shape == (2, 20)
    np.testing.assert_array_equal(records.response, 2.0 * np.array([h[:, 1] for h in hits]))
    assert "response Acc (x 2 given: V to SI)" in records.channels
    path.write_text(path.read_text().replace("1,000000E-3", "0,000977"))
    with pytest.warns(UserWarning, match="Delta_X '0,000977' has 3 significant digits"):
        records = read_hammer_records([path], fs=1024.0, response_scale=2.0)
    assert records.fs == 1024.0


def test_a_csv_headers_units_are_scaled_to_si(tmp_path):
    """A CSV whose header gives units: time in ms, force in kN, acceleration in g are
    scaled to s, N and m/s^2 and said (the g had been read as m/s^2, the ms as s: a
    restitution of 0.81 for 0.62, a rate of 25.6 Hz); a unit not known is refused, a unit
    of another quantity too; SI units and none change nothing; the response's unit says
    what it is."""
    from modalid._hammer_files import read_hammer_records

    n, fs = 64, 1000.0
    t = np.arange(n) / fs
    force = np.exp(-((np.arange(n) - 5) / 1.5) ** 2)
    acc = np.sin(np.arange(n) / 3.0)
    path = tmp_path / "hit.csv"
    path.write_text("Time (ms),Force [kN],Acceleration (g)\n"
                    + "".join(f"{1e3 * a:.17g},{b:.17g},{c:.17g}\n"
                              for a, b, c in zip(t, force, acc)))
    records = read_hammer_records([path])
    assert records.fs == pytest.approx(fs)
    np.testing.assert_allclose(records.force[0], 1000.0 * force)
    np.testing.assert_allclose(records.response[0], 9.80665 * acc)
    assert "(x 9.80665: g to SI)" in records.channels and "(x 1000: kN to SI)" in records.channels
    path.write_text("t (s),force (mV),acceleration (m/s^2)\n"
                    + "".join(f"{a:.17g},{b:.17g},{c:.17g}\n" for a, b, c in zip(t, force, acc)))
    with pytest.raises(ValueError, match=r"force channel 'force \(mV\)' is in 'mV', a unit "
                                         r"not known here"):
        read_hammer_records([path])
    records = read_hammer_records([path], force_scale=0.5)
    np.testing.assert_allclose(records.force[0], 0.5 * force)
    np.testing.assert_allclose(records.response[0], acc)
    assert records.response_type == "acceleration"
    for header, error in (("t (s),force (g),acceleration (m/s^2)",
                           r"force channel 'force \(g\)' is in 'g', a unit of acceleration"),
                          ("t (s),force (N),acceleration (m/s)",
                           r"'acceleration \(m/s\)' says acceleration by its name, "
                           r"velocity by its unit"),
                          ("t (Hz),force (N),response (mm)",
                           r"time channel 't \(Hz\)' is in 'Hz'")):
        path.write_text(header + "\n" + "".join(f"{a:.17g},{b:.17g},{c:.17g}\n"
                                                for a, b, c in zip(t, force, acc)))
        with pytest.raises(ValueError, match=error):
            read_hammer_records([path])
    path.write_text("t (s),force (N),response (mm)\n"
                    + "".join(f"{a:.17g},{b:.17g},{c:.17g}\n" for a, b, c in zip(t, force, acc)))
    records = read_hammer_records([path])
    assert records.response_type == "displacement"
    np.testing.assert_allclose(records.response[0], 1e-3 * acc)
