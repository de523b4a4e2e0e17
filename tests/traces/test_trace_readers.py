import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uma.errors import TraceError
from uma.traces import Trace, read_trace, sniff_format, write_uma_csv


def traces(shared_data):
    return shared_data / "traces"


def test_labelled_csv_keeps_technologies_and_gprs_outage(shared_data):
    trace = read_trace(traces(shared_data) / "ucc-5g-raca2020" / "B_2019.12.02_09.39.35.csv")
    assert {"3G", "GPRS", "LTE"} <= set(trace.technologies)
    gprs = np.array([tech == "GPRS" for tech in trace.technologies])
    widths = np.diff(np.append(trace.times_s, trace.duration_s))
    gprs_s = widths[gprs].sum()
    assert 70 <= gprs_s <= 90
    assert trace.rates_kbps[gprs].max() == 0.0  # the 80 s of GPRS at 0 kbit/s


def test_hsdpa_log_stops_at_counter_reset(shared_data):
    trace = read_trace(traces(shared_data) / "riiser-hsdpa-raw" / "report.2010-09-28_1407CEST.log")
    assert len(trace.times_s) == 457
    assert 400 < trace.duration_s < 520
    assert 500 < trace.mean_rate_kbps < 6000


def test_mahimahi_rates(shared_data):
    trace = read_trace(traces(shared_data) / "mahimahi" / "TMobile-UMTS-driving.down")
    assert (
        sniff_format(traces(shared_data) / "mahimahi" / "TMobile-UMTS-driving.down") == "mahimahi"
    )
    assert 100 < trace.mean_rate_kbps < 10_000
    assert (trace.rates_kbps < 100).mean() > 0.05  # long stretches below 100 kbit/s
    # Each opportunity carries 12,000 bits; 500 ms bins quantise rates to 24 kbit/s.
    assert np.allclose(np.mod(trace.rates_kbps, 24.0), 0.0)


@pytest.mark.parametrize(
    "relative, fmt",
    [
        ("pensieve-cooked/norway_car_7", "pensieve"),
        ("pensieve-cooked/bus.ljansbakken-oslo-report.2010-09-28_1407CEST.log", "pensieve"),
        ("mp-traces-wifi-cellular/8_5_wifi.csv", "bytes-per-sec"),
        ("mp-traces-wifi-cellular/8_5_cellular.csv", "bytes-per-sec"),
        ("nyu-mets/QTrain.csv", "nyu-mets"),
        ("mahimahi/Verizon-EVDO-driving.down", "mahimahi"),
        ("ucc-5g-raca2020/B_2019.12.16_11.49.59.csv", "labelled-csv"),
    ],
)
def test_every_format_reads_real_files(shared_data, relative, fmt):
    path = traces(shared_data) / relative
    assert sniff_format(path) == fmt
    trace = read_trace(path, format=fmt)
    assert trace.duration_s > 30
    assert np.all(np.isfinite(trace.rates_kbps)) and trace.rates_kbps.min() >= 0
    assert trace.mean_rate_kbps > 0


def test_qtrain_outages_are_zero(shared_data):
    trace = read_trace(traces(shared_data) / "nyu-mets" / "QTrain.csv")
    assert (trace.rates_kbps == 0).sum() >= 100  # 101 one-second samples at 0 in the subway


def test_wifi_fades_out_in_8_5(shared_data):
    trace = read_trace(traces(shared_data) / "mp-traces-wifi-cellular" / "8_5_wifi.csv")
    first, last = trace.rates_kbps[:20].mean(), trace.rates_kbps[-20:].mean()
    assert last < first


@pytest.mark.parametrize(
    "text, message",
    [
        ("time_s,rate_kbps,technology\n0,100,3G\n1,nan,3G\n", "line 3 of .*rate"),
        ("time_s,rate_kbps,technology\n0,100,3G\n1,-5,3G\n", "line 3 of .*>= 0"),
        ("time_s,rate_kbps,technology\n0,100,3G\n1,abc,3G\n", "line 3 of .*'abc'"),
        ("time_s,rate_kbps,technology\n0,100,3G\n2,100,3G\n1,50,3G\n", "line 4 of .*after"),
        ("time_s,rate_kbps,technology\n", "no samples"),
        ("", "no samples"),
        ("time_s,kbps\n0,1\n", "line 1 of .*expected 'time_s,rate_kbps,technology'"),
        ("time_s,rate_kbps,technology\n0,1,3G,extra\n", "line 2 of"),
        ("1.0\t2.0\n0.5\t2.0\n", "line 2 of .*after"),
        ("10,Gbits/sec\n", "line 1 of .*unit"),
    ],
)
def test_bad_traces_name_the_line(tmp_path, text, message):
    path = tmp_path / "trace.csv"
    path.write_text(text)
    with pytest.raises(TraceError, match=message):
        read_trace(path)


def test_binary_and_missing_files(tmp_path):
    path = tmp_path / "x.bin"
    path.write_bytes(b"\xff\xfe\x00\x81" * 10)
    with pytest.raises(TraceError, match="not a text file"):
        read_trace(path)
    with pytest.raises(TraceError, match="no such trace file"):
        read_trace(tmp_path / "none.csv")
    with pytest.raises(TraceError, match="unknown trace format 'csv'"):
        read_trace(path, format="csv")


rates = st.lists(
    st.floats(min_value=0, max_value=1e6, allow_nan=False, allow_infinity=False),
    min_size=1,
    max_size=30,
)


@given(rates=rates, data=st.data())
@settings(max_examples=60, deadline=None)
def test_uma_csv_round_trip(tmp_path_factory, rates, data):
    widths = data.draw(
        st.lists(st.floats(min_value=0.01, max_value=100), min_size=len(rates), max_size=len(rates))
    )
    techs = data.draw(
        st.lists(
            st.sampled_from(["", "3G", "GPRS", "GSM", "WLAN"]),
            min_size=len(rates),
            max_size=len(rates),
        )
    )
    times = np.concatenate(([0.0], np.cumsum(widths)[:-1]))
    if np.any(np.diff(times) <= 0):
        return
    trace = Trace(times, np.array(rates), tuple(techs), float(times[-1] + widths[-1]), "t")
    path = tmp_path_factory.mktemp("rt") / "t.csv"
    write_uma_csv(trace, path)
    back = read_trace(path)
    assert np.array_equal(back.times_s, trace.times_s)
    assert np.array_equal(back.rates_kbps, trace.rates_kbps)
    assert back.technologies == trace.technologies
    assert back.duration_s == trace.duration_s


@given(line=st.text(max_size=40))
@settings(max_examples=150, deadline=None)
def test_any_garbage_line_is_a_trace_error_or_a_valid_trace(tmp_path_factory, line):
    path = tmp_path_factory.mktemp("g") / "t.csv"
    path.write_text("time_s,rate_kbps,technology\n0,10,3G\n" + line.replace("\r", "") + "\n")
    try:
        trace = read_trace(path)
    except TraceError as err:
        assert "t.csv" in str(err)
    else:
        assert np.all(np.isfinite(trace.rates_kbps)) and trace.rates_kbps.min() >= 0
        assert math.isfinite(trace.duration_s)
