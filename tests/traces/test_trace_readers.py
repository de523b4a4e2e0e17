"""Every reader on the real files in ../shared/data/traces (skipped when that folder is absent)."""

import numpy as np
import pytest

from uma.traces import read_mahimahi, read_trace, sniff_format, write_uma_csv


@pytest.fixture(scope="module")
def traces(shared_data):
    return shared_data / "traces"


@pytest.mark.parametrize(
    "relative, fmt, steps, duration_s",
    [
        ("mahimahi/TMobile-UMTS-driving.down", "mahimahi", 9285, 928.424),
        ("mahimahi/Verizon-EVDO-driving.up", "mahimahi", 10648, 1064.718),
        ("pensieve-cooked/norway_car_7", "pensieve", 141, None),
        ("pensieve-cooked/trace_10730_http---www.facebook.com", "pensieve", 336, 1680.0),
        ("riiser-hsdpa-raw/report.2010-09-28_1407CEST.log", "hsdpa-log", 457, None),
        ("ucc-5g-raca2020/B_2019.12.16_11.49.59.csv", "labelled-csv", 342, 394.0),
        ("mp-traces-wifi-cellular/8_5_wifi.csv", "bytes-per-sec", 100, 100.0),
        ("mp-traces-wifi-cellular/7_2_cellular.csv", "bytes-per-sec", 100, 100.0),
        ("nyu-mets/QTrain.csv", "nyu-mets", 2404, 2404.0),
        ("nyu-mets/bus62.csv", "nyu-mets", 3293, 3293.0),
        ("nyu-mets/BB62.txt.gz", "nyu-mets-multivariate", 22005, 22005.0),
    ],
)
def test_every_format_sniffed_and_read(traces, relative, fmt, steps, duration_s):
    path = traces / relative
    assert sniff_format(path) == fmt
    trace = read_trace(path)
    assert trace == read_trace(path, format=fmt)
    assert len(trace) == steps
    if duration_s is not None:
        assert trace.duration_s == pytest.approx(duration_s)
    assert np.all(np.isfinite(trace.rates_kbps)) and trace.rates_kbps.min() >= 0
    assert trace.source == path.name


def test_mahimahi_keeps_every_opportunity(traces):
    for name, mean_kbps in (
        ("TMobile-UMTS-driving.down", 2019.7),
        ("Verizon-EVDO-driving.down", 520.5),
        ("Verizon-LTE-short.down", 5027.6),
    ):
        path = traces / "mahimahi" / name
        lines = path.read_text().split()
        trace = read_trace(path)
        # every 1500-byte opportunity is in the trace, over the file's period (its last stamp)
        assert trace.duration_s == float(lines[-1]) / 1000
        bits = trace.mean_rate_kbps * trace.duration_s * 1000
        assert bits == pytest.approx(len(lines) * 12000, rel=1e-9)
        assert trace.mean_rate_kbps == pytest.approx(mean_kbps, abs=0.1)


def test_mahimahi_bins(traces):
    path = traces / "mahimahi" / "TMobile-UMTS-driving.down"
    trace = read_trace(path)
    assert np.allclose(np.diff(trace.times_s), 0.1)
    full = trace.rates_kbps[:-1]
    assert np.allclose(np.mod(full, 120.0), 0.0)  # one packet in 100 ms = 120 kbit/s
    # The last bin is cut at the period (928,424 ms): 24 ms wide, its rate over those 24 ms.
    assert trace.widths_s[-1] == pytest.approx(0.024)
    assert trace.rates_kbps[-1] * 0.024 * 1000 % 12000 == pytest.approx(0.0, abs=1e-6)
    assert (trace.rates_kbps < 100).mean() > 0.05  # long stretches below 100 kbit/s
    coarse = read_trace(path, bin_ms=500)
    assert len(coarse) == 1857
    assert coarse.mean_rate_kbps == pytest.approx(trace.mean_rate_kbps)
    assert read_mahimahi(path, bin_ms=500) == coarse


def test_hsdpa_log_stops_where_the_log_starts_over(traces):
    path = traces / "riiser-hsdpa-raw" / "report.2010-09-28_1407CEST.log"
    lines = path.read_text().splitlines()
    assert len(lines) == 4 * 457 and lines[457] == lines[0]  # the shared copy repeats it 4x
    trace = read_trace(path)
    assert len(trace) == 457
    last = lines[456].split()
    first = lines[0].split()
    # from the start of the first interval to the last stamp
    assert trace.duration_s == pytest.approx((int(last[1]) - int(first[1]) + int(first[5])) / 1000)
    assert trace.rates_kbps[0] == pytest.approx(int(first[4]) * 8 / int(first[5]))
    assert 1000 < trace.mean_rate_kbps < 5000


def test_raw_hsdpa_log_and_its_pensieve_copy_line_up(traces):
    raw = read_trace(traces / "riiser-hsdpa-raw" / "report.2010-09-28_1407CEST.log")
    cooked = read_trace(
        traces / "pensieve-cooked" / "bus.ljansbakken-oslo-report.2010-09-28_1407CEST.log"
    )
    # Pensieve kept the first 135 samples as they were, then dropped the low ones.
    assert np.allclose(raw.rates_kbps[:135], cooked.rates_kbps[:135], rtol=1e-6)
    assert np.allclose(raw.times_s[:135], cooked.times_s[:135], atol=0.005)
    assert raw.rates_kbps.min() < 100 < cooked.rates_kbps.min()


def test_labelled_csv_gprs_outage_and_handovers(traces):
    path = traces / "ucc-5g-raca2020" / "B_2019.12.02_09.39.35.csv"
    trace = read_trace(path)
    assert set(trace.technologies) == {"3G", "GPRS", "LTE"}
    gprs = np.array([tech == "GPRS" for tech in trace.technologies])
    assert trace.widths_s[gprs].sum() == pytest.approx(80.0)  # 78 rows over 80 s
    assert trace.rates_kbps[gprs].max() == 0.0
    assert len(trace) == 972  # 1019 rows, 47 of them sharing a second with the row before
    assert trace.duration_s == 1086.0  # 09:39:35 to 09:57:40, plus the last second
    assert trace.technology_at(0) == "LTE"
    split = read_trace(path, duplicates="split")
    assert len(split) == 1019
    assert split.mean_rate_kbps == pytest.approx(trace.mean_rate_kbps)


def test_labelled_csv_5g_file(traces):
    trace = read_trace(traces / "ucc-5g-raca2020" / "B_2020.02.13_13.03.24.csv")
    assert set(trace.technologies) == {"3G", "LTE", "5G"}
    changes = sum(a != b for a, b in zip(trace.technologies, trace.technologies[1:], strict=False))
    assert changes >= 5  # 5G <-> LTE <-> 3G handovers kept


def test_nyu_mets_units_and_subway_outage(traces):
    scale = {"Mbits/sec": 1000, "Kbits/sec": 1, "bits/sec": 0.001}
    units = set()
    for name in ("QTrain.csv", "bus62.csv"):
        path = traces / "nyu-mets" / name
        rows = [line.split(",") for line in path.read_text().split()]
        expected = [float(value) * scale[unit] for value, unit in rows]
        assert np.allclose(read_trace(path).rates_kbps, expected, rtol=1e-12)
        units |= {unit for _, unit in rows}
    assert units == set(scale)  # all three units occur in these two files
    qtrain = read_trace(traces / "nyu-mets" / "QTrain.csv")
    assert (qtrain.rates_kbps == 0).sum() >= 100  # 101 one-second samples at 0 underground


def test_wifi_fades_out_while_cellular_stays(traces):
    wifi = read_trace(traces / "mp-traces-wifi-cellular" / "8_5_wifi.csv")
    cell = read_trace(traces / "mp-traces-wifi-cellular" / "8_5_cellular.csv")
    assert wifi.rates_kbps[-20:].mean() < 0.5 * wifi.rates_kbps[:20].mean()
    assert cell.rates_kbps[-20:].mean() > 1000
    assert wifi.rates_kbps[0] == pytest.approx(3207630 * 8 / 1000)  # row "1,3207630"


def test_every_real_file_converts_to_uma_csv_exactly(traces, tmp_path):
    for path in sorted(traces.glob("*/*")):
        if path.suffix in (".md", ".txt", ".gz") or path.name == "README":
            continue
        trace = read_trace(path)
        write_uma_csv(trace, tmp_path / "t.csv")
        assert read_trace(tmp_path / "t.csv") == trace, path.name
