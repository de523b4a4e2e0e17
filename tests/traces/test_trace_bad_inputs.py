"""Malformed trace files: always a TraceError naming the file and the line, never another error."""

import re

import pytest

from uma.errors import TraceError
from uma.traces import read_trace, sniff_format

# One small valid file per format (line numbers below refer to these).
VALID = {
    "mahimahi": "0\n3\n3\n10\n25\n",
    "pensieve": "0.0\t1.5\n1.0\t2.0\n2.5 0.5\n",
    "hsdpa-log": (
        "1285675666 310761 59.88 10.76 288648 1008\n"
        "1285675667 311771 59.88 10.76 171588 1010\n"
        "1285675668 312772 59.88 10.76 365824 1001\n"
    ),
    "labelled-csv": (
        "Timestamp,NetworkMode,DL_bitrate\n"
        "2019.12.02_09.39.35,LTE,170\n"
        "2019.12.02_09.39.36,HSPA+,0\n"
        "2019.12.02_09.39.38,GPRS,12\n"
    ),
    "bytes-per-sec": "1,1000\n2,2000\n3,0\n",
    "nyu-mets": "1.5,Mbits/sec\n300,Kbits/sec\n0,bits/sec\n",
    "nyu-mets-multivariate": (
        "18.8,6,0,-88,-15,2,0,2100\n0,6,1,-101,-15,4,0.35,700\n2.5,3,0,-90,-14,2,3.57,2100\n"
    ),
    "uma-csv": "time_s,rate_kbps,technology\n# duration_s=4\n0,100,3G\n1,0,\n2.5,50,GPRS\n",
}


def write(tmp_path, text, name="trace.txt"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("fmt", sorted(VALID))
def test_valid_examples_read_and_sniff(tmp_path, fmt):
    path = write(tmp_path, VALID[fmt])
    assert sniff_format(path) == fmt
    trace = read_trace(path)
    assert trace == read_trace(path, format=fmt) and trace.duration_s > 0


def test_small_examples_mean_what_they_say(tmp_path):
    mahimahi = read_trace(write(tmp_path, VALID["mahimahi"]), bin_ms=10)
    # 25 ms period; bins [0,10) [10,20) [20,25); the stamp 25 is the next period's first.
    assert mahimahi.rates_kbps.tolist() == [4 * 1200.0, 1200.0, 0.0]
    assert mahimahi.duration_s == 0.025
    pensieve = read_trace(write(tmp_path, VALID["pensieve"]))
    assert pensieve.times_s.tolist() == [0.0, 1.0, 2.0]  # rates cover the interval before
    assert pensieve.rates_kbps.tolist() == [1500.0, 2000.0, 500.0]
    assert pensieve.duration_s == 3.5
    labelled = read_trace(write(tmp_path, VALID["labelled-csv"]))
    assert labelled.times_s.tolist() == [0.0, 1.0, 3.0]
    assert labelled.technologies == ("LTE", "3G", "GPRS")
    assert labelled.duration_s == 4.0
    nyu = read_trace(write(tmp_path, VALID["nyu-mets"]))
    assert nyu.rates_kbps.tolist() == [1500.0, 300.0, 0.0]
    multivariate = read_trace(write(tmp_path, VALID["nyu-mets-multivariate"]))
    assert multivariate.rates_kbps.tolist() == [18800.0, 0.0, 2500.0]  # the first column, Mbit/s
    assert multivariate.times_s.tolist() == [0.0, 1.0, 2.0] and multivariate.duration_s == 3.0
    assert multivariate.technologies == ("", "", "")
    own = read_trace(write(tmp_path, VALID["uma-csv"]))
    assert own.technologies == ("3G", "", "GPRS") and own.duration_s == 4.0


BAD = [
    # (format, text, message regex)
    ("mahimahi", "0\n3\nnan\n", r"line 3 of .*: expected a finite delivery time in ms, got 'nan'"),
    ("mahimahi", "0\n5\n4\n", r"line 3 of .*: expected a delivery time not before 5 ms, got 4"),
    ("mahimahi", "0\n-5\n", r"line 2 of .*: expected a whole number"),
    ("mahimahi", "0\n0\n", r"line 2 of .*: expected the last delivery time \(the period\) > 0"),
    ("mahimahi", "0\n\n# note\n", r"line 3 of .*got '# note'"),
    (
        "mahimahi",
        "0\n2233720368547\n",
        r"line 2 of .*at most 10,000,000 bins of 100 ms, got 2233720368547 ms",
    ),
    ("pensieve", "0\t1\n1\tnan\n", r"line 2 of .*: expected a finite rate in Mbit/s, got 'nan'"),
    ("pensieve", "0\t1\n1\t-2\n", r"line 2 of .*: expected rate in Mbit/s >= 0, got '-2'"),
    ("pensieve", "0\t1\n1\tinf\n", r"line 2 of .*finite"),
    ("pensieve", "0\t1\n2\t1\n1\t1\n", r"line 3 of .*: expected a time after 2 s .*got 1 s"),
    ("pensieve", "0\t1\n0\t1\n", r"line 2 of .*expected a time after 0 s"),
    ("pensieve", "0\t1\n1\t2\t3\n", r"line 2 of .*: expected 2 fields 'time_s<TAB>Mbit/s', got 3"),
    ("pensieve", "0\t1\n1\t1_000\n", r"line 2 of .*got '1_000'"),
    ("hsdpa-log", VALID["hsdpa-log"] + "1 1 1 1 1\n", r"line 4 of .*expected 6 fields"),
    (
        "hsdpa-log",
        VALID["hsdpa-log"] + "1285675669 312000 59.88 10.76 1 1009\n",
        r"line 4 of .*the counter went back without the log starting over",
    ),
    (
        "hsdpa-log",
        VALID["hsdpa-log"].replace("171588 1010", "171588 0"),
        r"line 2 of .*: expected interval in ms > 0, got '0'",
    ),
    (
        "labelled-csv",
        "Timestamp,NetworkMode,DL_bitrate\n2019.12.02_09.39.35,LTE,-1\n",
        r"line 2 of .*DL_bitrate in kbit/s >= 0, got '-1'",
    ),
    (
        "labelled-csv",
        "Timestamp,NetworkMode,DL_bitrate\n2019.12.02_09.39.35,LTE,1\n2019.12.02_09.39.34,LTE,1\n",
        r"line 3 of .*: expected a Timestamp not before the row at line 2",
    ),
    (
        "labelled-csv",
        "Timestamp,NetworkMode,DL_bitrate\n2019.12.02_09.39.35,CB-radio,1\n",
        r"line 2 of .*: expected a NetworkMode naming a technology .*got 'CB-radio'",
    ),
    (
        "labelled-csv",
        "Timestamp,NetworkMode,DL_bitrate\n2019.13.02_09.39.35,LTE,1\n",
        r"line 2 of .*real date",
    ),
    (
        "labelled-csv",
        "Timestamp,NetworkMode,DL_bitrate\n2019.12.02_09.39.35,LTE\n",
        r"line 2 of .*: expected 3 comma-separated fields as in the header, got 2",
    ),
    ("labelled-csv", "Timestamp,NetworkMode,DL_bitrate\n", r"no samples \(a header and no rows\)"),
    ("bytes-per-sec", "1,100\n2,-100\n", r"line 2 of .*bytes per second >= 0"),
    ("bytes-per-sec", "1,100\n2,100,3\n", r"line 2 of .*expected 2 fields 'sec,bytes_per_sec'"),
    ("nyu-mets", "1,Mbits/sec\n2,Gbytes/sec\n", r"line 2 of .*unit among .*got 'Gbytes/sec'"),
    ("nyu-mets", "1,Mbits/sec\nNaN,Mbits/sec\n", r"line 2 of .*finite rate, got 'NaN'"),
    (
        "nyu-mets-multivariate",
        "1,2,0,-88,-15,2,0,2100\n1,2,0,-88,x,2,0,2100\n",
        r"line 2 of .*a number \(RSRQ\), got 'x'",
    ),
    (
        "nyu-mets-multivariate",
        "1,2,0,-88,-15,2,0,2100\n-1,2,0,-88,-15,2,0,2100\n",
        r"line 2 of .*rate >= 0, got '-1'",
    ),
    (
        "nyu-mets-multivariate",
        "1,2,0,-88,-15,2,0,2100\n1,2,0,-88,-15,2,0\n",
        r"line 2 of .*expected 8 fields 'Mbit/s,neighbours,eNodeB_changed",
    ),
    ("uma-csv", "time_s,rate_kbps,technology\n0,100,3G\n1,nan,3G\n", r"line 3 of .*finite rate"),
    ("uma-csv", "time_s,rate_kbps,technology\n0,100,3G\n1,-5,3G\n", r"line 3 of .*>= 0"),
    ("uma-csv", "time_s,rate_kbps,technology\n0,100,3G\n1,abc,3G\n", r"line 3 of .*'abc'"),
    (
        "uma-csv",
        "time_s,rate_kbps,technology\n0,100,3G\n2,100,3G\n1,50,3G\n",
        r"line 4 of .*expected a time after 2 s",
    ),
    ("uma-csv", "time_s,rate_kbps,technology\n1,100,3G\n", r"line 2 of .*first step at time 0"),
    ("uma-csv", "time_s,rate_kbps,technology\n0,1,3G,x\n", r"line 2 of .*expected 'time_s,"),
    ("uma-csv", "time_s,rate_kbps\n0,1,3G\n", r"line 2 of .*expected 'time_s,rate_kbps', got"),
    ("uma-csv", "time_s,rate_kbps,technology\n0,1,Pigeon\n", r"line 2 of .*got 'Pigeon'"),
    ("uma-csv", "time_s,kbps\n0,1\n", r"line 1 of .*expected 'time_s,rate_kbps,technology'"),
    (
        "uma-csv",
        "time_s,rate_kbps,technology\n# duration_s=1\n0,1,\n2,1,\n",
        r"line 2 of .*expected duration_s after the last step's start 2 s \(line 4\)",
    ),
    (
        "uma-csv",
        "time_s,rate_kbps\n# duration_s=5\n# duration_s=6\n0,1\n",
        r"line 3 of .*a second \(the first is line 2\)",
    ),
    ("uma-csv", "time_s,rate_kbps,technology\n", r"no samples"),
    ("uma-csv", "# only a comment\n", r"no samples \(no data lines\)"),
]


@pytest.mark.parametrize("fmt, text, message", BAD)
def test_bad_files_name_the_line(tmp_path, fmt, text, message):
    path = write(tmp_path, text)
    with pytest.raises(TraceError, match=message):
        read_trace(path, format=fmt)


@pytest.mark.parametrize("fmt", sorted(VALID))
@pytest.mark.parametrize("text", ["", "\n\n  \n", "\ufeff"])
def test_empty_files(tmp_path, fmt, text):
    path = write(tmp_path, text)
    with pytest.raises(TraceError, match=re.escape(str(path)) + r": no samples"):
        read_trace(path, format=fmt)
    with pytest.raises(TraceError, match="no samples"):
        read_trace(path)


def test_crlf_and_bom_are_read(tmp_path):
    path = tmp_path / "t.csv"
    path.write_bytes(b"\xef\xbb\xbftime_s,rate_kbps,technology\r\n0,5,LTE\r\n1,6,\r\n")
    trace = read_trace(path)
    assert trace.rates_kbps.tolist() == [5.0, 6.0] and trace.technologies == ("LTE", "")


def test_line_numbers_match_an_editor(tmp_path):
    # A form feed is a line break for str.splitlines (which would call the bad line 4), not
    # for an editor or for uma; trailing, it is only blank space.
    path = write(tmp_path, "0\t1\n1\t2\x0c\n2\tx\n")
    with pytest.raises(TraceError, match=r"line 3 of .*got 'x'"):
        read_trace(path, format="pensieve")


def test_unreadable_files_and_unknown_formats(tmp_path):
    binary = tmp_path / "x.bin"
    binary.write_bytes(b"\xff\xfe\x00\x81" * 10)
    with pytest.raises(
        TraceError,
        match=r"line 1 of .*x.bin: expected UTF-8 text, got binary data \(byte ",
    ):
        read_trace(binary)
    with pytest.raises(TraceError, match="no such trace file"):
        read_trace(tmp_path / "none.csv")
    with pytest.raises(TraceError, match="got a folder"):
        read_trace(tmp_path)
    path = write(tmp_path, VALID["pensieve"])
    with pytest.raises(
        TraceError,
        match="unknown trace format 'csv'; expected auto or one of mahimahi, pensieve, "
        "hsdpa-log, labelled-csv, bytes-per-sec, nyu-mets, nyu-mets-multivariate, uma-csv",
    ):
        read_trace(path, format="csv")
    with pytest.raises(TraceError, match="format pensieve takes no option bin_ms"):
        read_trace(path, bin_ms=10)
    with pytest.raises(TraceError, match="bin_ms: expected a duration > 0 ms"):
        read_trace(write(tmp_path, VALID["mahimahi"]), bin_ms=0)
    with pytest.raises(TraceError, match="duplicates: expected one of mean, split"):
        read_trace(write(tmp_path, VALID["labelled-csv"]), duplicates="max")


def test_sniffing_failures_list_the_formats(tmp_path):
    with pytest.raises(TraceError, match=r"line 2 of .*cannot tell the trace format.*nyu-mets"):
        read_trace(write(tmp_path, "\nhello world, this is no trace\n"))
    # A Mahimahi file by name gets the Mahimahi reader's own complaint.
    with pytest.raises(TraceError, match=r"line 2 of .*x\.down: expected a whole number"):
        read_trace(write(tmp_path, "0\n1.5\n", name="x.down"))


def test_a_misspelt_uma_header_gets_the_uma_reader(tmp_path):
    with pytest.raises(TraceError, match=r"line 1 of .*expected 'time_s,rate_kbps,technology'"):
        read_trace(write(tmp_path, "time_s,kbps\n0,1\n"))


def test_mixed_lines_are_not_guessed(tmp_path):
    # The first lines disagree on the format: auto refuses rather than picking one.
    with pytest.raises(TraceError, match="cannot tell the trace format"):
        read_trace(write(tmp_path, "1,100\n0\t1\n"))


def test_gzip_trace_is_read_and_a_broken_one_named(tmp_path):
    import gzip

    plain = write(tmp_path, VALID["pensieve"])
    packed = tmp_path / "trace.log.gz"
    packed.write_bytes(gzip.compress(VALID["pensieve"].encode()))
    assert read_trace(packed) == read_trace(plain)
    packed.write_bytes(gzip.compress(VALID["pensieve"].encode())[:20])
    with pytest.raises(
        TraceError, match=r"trace.log.gz: a gzip-compressed trace file that does not"
    ):
        read_trace(packed)
