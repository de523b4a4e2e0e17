"""Issue 28, items 3, 7 and 12: every key bounded by what a run can hold, named with its bound;
technologies named anywhere are uma's labels; estimator settings that contradict are refused."""

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uma.config import load_scenario
from uma.config.scenario import MAX_DURATION_S, MAX_WORK_PIXELS
from uma.errors import ConfigError

HEAD = "name: x\nroute:\n  - {technology: 3G, duration_s: 10}\n"


def load(tmp_path, text):
    path = tmp_path / "s.yaml"
    path.write_text(text)
    return load_scenario(path)


def refused(tmp_path, text, pattern):
    with pytest.raises(ConfigError) as caught:
        load(tmp_path, text)
    message = str(caught.value)
    assert "\n" not in message and re.search(pattern, message), message


numbers = st.floats(allow_nan=False, allow_infinity=False, min_value=1e-300, max_value=1e300)


@pytest.mark.parametrize("key", ["far_ring_head_radii", "head_ring_outlines"])
@settings(deadline=None, max_examples=60)  # file I/O on a loaded machine
@given(value=numbers)
def test_ring_sizes_are_bounded(tmp_path_factory, key, value):
    tmp_path = tmp_path_factory.mktemp("ring")
    text = HEAD + f"engine:\n  mbc: {{{key}: {value!r}}}\n"
    if 1 < value <= 8:
        assert getattr(load(tmp_path, text).engine.mbc, key) == value
    elif value > 8:
        refused(tmp_path, text, rf"s\.yaml:5 \(engine\.mbc\.{key}\): .* is above the maximum 8$")
    else:
        refused(tmp_path, text, rf"\(engine\.mbc\.{key}\): input should be greater than 1")


def test_the_bound_is_stated_as_the_issue_asks(tmp_path):
    refused(
        tmp_path,
        HEAD + "engine:\n  mbc: {far_ring_head_radii: 100000.0}\n",
        r"\(engine\.mbc\.far_ring_head_radii\): 100000 is above the maximum 8$",
    )


@settings(deadline=None, max_examples=60)  # file I/O on a loaded machine
@given(value=numbers)
def test_the_feedback_interval_is_bounded(tmp_path_factory, value):
    tmp_path = tmp_path_factory.mktemp("feedback")
    text = HEAD + f"feedback: {{interval_ms: {value!r}}}\n"
    if 10 <= value <= 60_000:
        assert load(tmp_path, text).feedback.interval_ms == value
    else:
        refused(tmp_path, text, r"\(feedback\.interval_ms\): .* is (below the minimum 10|above)")


@settings(deadline=None, max_examples=60)  # file I/O on a loaded machine
@given(width=st.integers(-10, 10**6), height=st.integers(-10, 10**6), fps=st.floats(1e-9, 1e9))
def test_picture_sizes_and_rates_are_bounded(tmp_path_factory, width, height, fps):
    tmp_path = tmp_path_factory.mktemp("picture")
    text = HEAD + f"source: {{width: {width}, height: {height}, fps: {fps!r}}}\n"
    within = 16 <= width <= 4096 and 16 <= height <= 4096 and fps <= 120
    even = width % 2 == 0 and height % 2 == 0
    fits = 10 * fps >= 1 and 10 * fps * width * height <= MAX_WORK_PIXELS
    if within and even and fits:
        assert load(tmp_path, text).source.width == width
    else:
        with pytest.raises(ConfigError, match=r"s\.yaml:\d+"):
            load(tmp_path, text)


@pytest.mark.parametrize(
    "text, pattern",
    [
        ("duration_s: 1000000000.0\n", r"\(duration_s\): 1000000000 is above the maximum 14400$"),
        ("duration_s: 0.000000001\n", r"duration_s \(1e-09\) x source.fps \(25\) holds no frame"),
        (
            "duration_s: 14000.0\nsource: {width: 3840, height: 2160, fps: 60.0}\n",
            r"duration_s \(14000\) x source.fps \(60\) x source.width \(3840\) x source.height "
            r"\(2160\) is 6.97e\+12 pixels to simulate, above the maximum 3e\+11",
        ),
        ("source: {width: 100000, height: 100000}\n", r"\(source\.width\): 100000 is above"),
        ("source: {fps: 1000000.0}\n", r"\(source\.fps\): 1000000 is above the maximum 120$"),
        ("downlink: {packet_bytes: 1}\n", r"\(downlink\.packet_bytes\): 1 is below the minimum 40"),
        ("seed: 100000000000000000000000\n", r"\(seed\): .* is above the maximum"),
        ("engine: {up_hold_ms: 1.0e+300}\n", r"\(engine\.up_hold_ms\): 1e\+300 is above"),
    ],
)
def test_runaway_values_are_refused(tmp_path, text, pattern):
    refused(tmp_path, HEAD + text, pattern)


def test_a_route_longer_than_a_run_may_be_needs_a_duration(tmp_path):
    route = "".join("  - {technology: 3G, duration_s: 10000}\n" for _ in range(2))
    refused(tmp_path, "name: x\nroute:\n" + route, r"route's 20000 s is above the maximum 14400")
    assert load(tmp_path, f"name: x\nduration_s: {MAX_DURATION_S}\nroute:\n" + route)


@pytest.mark.parametrize(
    "text, key",
    [
        (
            "engine:\n  switching: {low_technologies: [GSM, 6G]}\n",
            "engine.switching.low_technologies",
        ),
        ("downlink:\n  technologies: {6G: {delay_ms: 10}}\n", "downlink.technologies"),
    ],
)
def test_unknown_technologies_are_refused_everywhere(tmp_path, text, key):
    refused(
        tmp_path,
        HEAD + text,
        rf"\({re.escape(key)}\): expected technologies among GSM, GPRS, EDGE, 3G, LTE, 5G, WLAN, "
        r"got '6G'$",
    )


@settings(deadline=None, max_examples=60)  # file I/O on a loaded machine
@given(
    low=st.floats(1, 1e5),
    high=st.floats(1, 1e5),
    initial=st.floats(1, 1e5),
)
def test_estimator_settings_that_contradict_are_refused(tmp_path_factory, low, high, initial):
    tmp_path = tmp_path_factory.mktemp("estimator")
    text = HEAD + (
        f"engine:\n  estimator: {{min_kbps: {low!r}, max_kbps: {high!r}, initial_kbps: "
        f"{initial!r}}}\n"
    )
    if low <= initial <= high:
        assert load(tmp_path, text).engine.estimator.initial_kbps == initial
    else:
        refused(tmp_path, text, r"s\.yaml:5 \(engine\.estimator\): (min_kbps|initial_kbps)")
