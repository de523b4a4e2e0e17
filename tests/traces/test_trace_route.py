import numpy as np
import pytest

from uma.errors import TraceError
from uma.traces import RouteSegment, build_route, read_trace


def test_durations_add_up_and_labels_follow_segments():
    segments = [RouteSegment("WLAN", 10), RouteSegment("3G", 20.5), RouteSegment("GSM", 5)]
    route = build_route(segments, rng=3)
    assert route.duration_s == 35.5
    assert route.technology_at(5) == "WLAN"
    assert route.technology_at(10) == "3G"
    assert route.technology_at(30.4) == "3G"
    assert route.technology_at(30.5) == "GSM"
    assert route.technology_at(35.5) == "GSM"


def test_route_is_reproducible_from_a_seed():
    segments = [RouteSegment("GPRS", 60), RouteSegment("3G", 60)]
    a, b = build_route(segments, rng=7), build_route(segments, rng=7)
    assert a == b
    assert a != build_route(segments, rng=8)
    gen = np.random.default_rng(7)
    assert build_route(segments, rng=gen) == a
    assert build_route(segments, rng=gen) != a  # a Generator is advanced, not reset


def write(path, text):
    path.write_text(text)
    return path


def test_short_trace_loops_from_its_start_and_offset_applies(tmp_path):
    write(tmp_path / "t.csv", "time_s,rate_kbps,technology\n# duration_s=4\n0,100,\n2,200,\n")
    route = build_route([RouteSegment("3G", 10, trace="t.csv", offset_s=3)], base_dir=tmp_path)
    assert route.duration_s == 10
    # offset 3 s: 1 s of 200, then the file again from 0: 100, 200, 100, 200, 100 (cut)
    expected = [200, 100, 100, 200, 200, 100, 100, 200, 200, 100]
    assert [route.rate_kbps_at(t + 0.5) for t in range(10)] == expected
    assert set(route.technologies) == {"3G"}  # the file had no labels


def test_labels_from_the_file_win_unless_relabelled(tmp_path):
    path = write(
        tmp_path / "l.csv",
        "Timestamp,NetworkMode,DL_bitrate\n"
        "2019.12.02_09.39.35,LTE,170\n"
        "2019.12.02_09.39.36,-,80\n"
        "2019.12.02_09.39.37,GPRS,0\n",
    )
    kept = build_route([RouteSegment("3G", 3, trace=str(path))])
    assert kept.technologies == ("LTE", "", "GPRS")  # handovers kept; unknown stays unknown
    relabelled = build_route([RouteSegment("3G", 3, trace=str(path), relabel=True)])
    assert set(relabelled.technologies) == {"3G"}
    own = build_route([RouteSegment("", 3, trace=str(path))])
    assert own == kept


def test_scale_and_mixed_segments(tmp_path):
    write(tmp_path / "c.csv", "time_s,rate_kbps\n0,1000\n")
    route = build_route(
        [
            RouteSegment("WLAN", 2.5, trace="c.csv", scale=0.5),
            RouteSegment("GPRS", 3),
            RouteSegment("GPRS", 2, scale=0.0),  # an outage on GPRS
        ],
        rng=1,
        base_dir=tmp_path,
    )
    assert route.duration_s == 7.5
    assert route.rate_kbps_at(1.0) == 500.0
    assert route.technology_at(1.0) == "WLAN"
    assert route.rate_kbps_at(6.0) == 0.0 and route.technology_at(6.0) == "GPRS"


def test_errors_name_the_segment(tmp_path):
    write(tmp_path / "bad.csv", "time_s,rate_kbps,technology\n0,1,3G\n1,-4,3G\n")
    write(tmp_path / "ok.csv", "time_s,rate_kbps,technology\n0,100,WLAN\n")
    with pytest.raises(TraceError, match=r"route segment 1 \(trace bad.csv\): line 3 of .*>= 0"):
        build_route(
            [RouteSegment("3G", 3), RouteSegment("3G", 3, trace="bad.csv")],
            rng=0,
            base_dir=tmp_path,
        )
    with pytest.raises(
        TraceError, match=r"route segment 0 \(trace ok.csv\): offset_s 50 s is past"
    ):
        build_route([RouteSegment("3G", 3, trace="ok.csv", offset_s=50)], base_dir=tmp_path)
    with pytest.raises(TraceError, match=r"route segment 2 \(trace none.csv\): .*no such trace"):
        build_route(
            [RouteSegment("3G", 1), RouteSegment("3G", 1), RouteSegment("3G", 1, trace="none.csv")],
            base_dir=tmp_path,
        )
    with pytest.raises(TraceError, match="route: expected at least one segment"):
        build_route([])


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"technology": "Carrier pigeon", "duration_s": 3}, "technology among .*'Carrier pigeon'"),
        ({"technology": "", "duration_s": 3}, "technology among"),  # generated needs one
        ({"technology": "3G", "duration_s": 0}, "duration_s > 0"),
        ({"technology": "3G", "duration_s": float("nan")}, "duration_s > 0"),
        ({"technology": "3G", "duration_s": 1, "trace": "x", "offset_s": -1}, "offset_s >= 0"),
        ({"technology": "3G", "duration_s": 1, "scale": -1}, "scale >= 0"),
        ({"technology": "3G", "duration_s": 1, "trace": "x", "format": "csv"}, "format auto or"),
        ({"technology": "3G", "duration_s": 1, "offset_s": 5}, "apply to a trace file"),
    ],
)
def test_segments_are_validated_when_built(kwargs, message):
    with pytest.raises(TraceError, match=message):
        RouteSegment(**kwargs)


def test_segment_technology_is_normalised():
    assert RouteSegment("hspa+", 1).technology == "3G"


def test_real_commute(shared_data):
    traces = shared_data / "traces"
    route = build_route(
        [
            RouteSegment("WLAN", 60, trace="mp-traces-wifi-cellular/8_5_wifi.csv"),
            RouteSegment(
                "3G", 120, trace="ucc-5g-raca2020/B_2019.12.02_09.39.35.csv", offset_s=800
            ),
            RouteSegment("GSM", 40),
            RouteSegment("3G", 150, trace="mahimahi/Verizon-LTE-short.down"),  # 140 s: loops
        ],
        rng=1,
        base_dir=traces,
    )
    assert route.duration_s == pytest.approx(370.0)
    assert route.technology_at(30) == "WLAN"
    # The UCC drive from 800 s: HSPA+ (3G), then its GPRS stretch at 0 kbit/s from 860 s.
    assert route.technology_at(60 + 30) == "3G"
    assert route.technology_at(60 + 70) == "GPRS" and route.rate_kbps_at(60 + 70) == 0
    assert route.technology_at(200) == "GSM"
    mahimahi = read_trace(traces / "mahimahi" / "Verizon-LTE-short.down")
    assert route.rate_kbps_at(220 + 140 + 0.05) == mahimahi.rate_kbps_at(0.05)  # looped
    assert route.technology_at(365) == "3G"
