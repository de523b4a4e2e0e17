import numpy as np
import pytest

from uma.errors import TraceError
from uma.traces import RouteSegment, Trace, build_route, generate, technology_defaults


def test_route_durations_add_up_and_labels_follow_segments():
    segments = [RouteSegment("WLAN", 10), RouteSegment("3G", 20), RouteSegment("GSM", 5)]
    route = build_route(segments, rng=3)
    assert route.duration_s == pytest.approx(35)
    assert route.technology_at(5) == "WLAN"
    assert route.technology_at(15) == "3G"
    assert route.technology_at(34) == "GSM"


def test_route_is_reproducible_from_seed():
    segments = [RouteSegment("GPRS", 60), RouteSegment("3G", 60)]
    a, b = build_route(segments, rng=7), build_route(segments, rng=7)
    c = build_route(segments, rng=8)
    assert np.array_equal(a.rates_kbps, b.rates_kbps)
    assert not np.array_equal(a.rates_kbps, c.rates_kbps)


@pytest.mark.parametrize(
    "tech, low, high", [("GSM", 4, 10), ("GPRS", 10, 60), ("3G", 150, 2000), ("WLAN", 1500, 20000)]
)
def test_generated_rates_sit_in_the_technology_range(tech, low, high):
    trace = generate(tech, 600, rng=1)
    nonzero = trace.rates_kbps[trace.rates_kbps > 0]
    assert low <= np.median(nonzero) <= high
    assert nonzero.min() >= technology_defaults(tech).min_kbps


def test_short_trace_loops_and_offset_applies(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("time_s,rate_kbps,technology\n# duration_s=4\n0,100,\n2,200,\n")
    route = build_route([RouteSegment("3G", 10, trace=str(path), offset_s=2)])
    assert route.duration_s == pytest.approx(10)
    assert route.rate_kbps_at(0.5) == 200
    assert route.rate_kbps_at(2.5) == 100
    assert route.rate_kbps_at(4.5) == 200
    assert set(route.technologies) == {"3G"}


def test_relative_trace_path_and_errors_name_segment(tmp_path):
    (tmp_path / "t.csv").write_text("time_s,rate_kbps,technology\n0,100,WLAN\n")
    route = build_route([RouteSegment("3G", 3, trace="t.csv")], base_dir=tmp_path)
    assert route.technologies[0] == "WLAN"  # the file's own label wins
    with pytest.raises(
        TraceError, match="route segment 1: cannot generate rates for technology 'Carrier pigeon'"
    ):
        build_route([RouteSegment("3G", 3), RouteSegment("Carrier pigeon", 3)], rng=0)
    with pytest.raises(TraceError, match="route segment 0: offset_s"):
        build_route([RouteSegment("3G", 3, trace="t.csv", offset_s=50)], base_dir=tmp_path)


def test_trace_rate_at_step_edges_and_window():
    trace = Trace(np.array([0.0, 1.0, 3.0]), np.array([10.0, 0.0, 30.0]), ("a", "b", "c"), 5.0)
    assert trace.rate_kbps_at(0.999) == 10
    assert trace.rate_kbps_at(1.0) == 0
    assert trace.rate_kbps_at(4.99) == 30
    part = trace.window(0.5, 3.0)
    assert part.times_s.tolist() == [0.0, 0.5, 2.5]
    assert part.duration_s == 3.0
    assert trace.mean_rate_kbps == pytest.approx((10 + 0 + 60) / 5)


def test_trace_validation():
    with pytest.raises(TraceError, match="no samples"):
        Trace(np.array([]), np.array([]), (), 1.0)
    with pytest.raises(TraceError, match="finite rate"):
        Trace(np.array([0.0]), np.array([np.nan]), ("",), 1.0)
    with pytest.raises(TraceError, match="does not cover"):
        Trace(np.array([0.0, 2.0]), np.array([1.0, 1.0]), ("", ""), 2.0)


def test_project_trace_reads_and_crosses_technologies():
    from uma.paths import traces_dir
    from uma.traces import read_trace

    trace = read_trace(traces_dir() / "cell-edge-fallback.csv")
    assert trace.duration_s == pytest.approx(80.0)
    assert {"3G", "GPRS", "GSM"} == set(trace.technologies)
