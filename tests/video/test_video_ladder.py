import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from uma.errors import ConfigError
from uma.video import EncoderSettings, H264Encoder, Ladder, Rung, load_ladder


def test_default_ladder_is_ascending_and_codable():
    ladder = load_ladder()
    rates = [r.rate_kbps for r in ladder.rungs]
    assert rates == sorted(rates) and len(set(rates)) == len(rates) >= 5
    assert ladder.rungs[0].rate_kbps <= 32 and ladder.rungs[-1].width == 352
    assert all(r.width % 2 == 0 and r.height % 2 == 0 and r.fps > 0 for r in ladder.rungs)
    assert ladder.source.endswith("h264.yaml")
    settings_ = ladder.encoder
    assert settings_.preset == "ultrafast" and "zerolatency" in settings_.tune
    for rung in (ladder.rungs[0], ladder.rungs[-1]):
        H264Encoder(rung.width, rung.height, rung.fps, rung.rate_kbps, **settings_.kwargs())


def test_encoder_section_is_read(tmp_path):
    path = tmp_path / "h.yaml"
    path.write_text(
        "encoder: {preset: veryfast, tune: 'zerolatency,psnr', keyint_frames: 50, vbv_frames: 2}\n"
        "rungs:\n  - {rate_kbps: 20, width: 128, height: 96, fps: 5}\n"
    )
    ladder = load_ladder(path)
    assert ladder.encoder == EncoderSettings("veryfast", "zerolatency,psnr", 50, 2.0)
    assert ladder.rungs == (Rung(20.0, 128, 96, 5.0),)


def test_rung_label():
    assert Rung(64, 256, 208, 12.5).label == "64k 256x208@12.5"


RUNG = "  - {rate_kbps: 20, width: 176, height: 144, fps: 5}\n"


@pytest.mark.parametrize(
    "body, message",
    [
        (
            "rungs:\n" + RUNG + "  - {rate_kbps: 40, width: 176, height: 144, fps: -1}\n",
            r"h\.yaml:3 \(rungs\[1\]\.fps\): expected a positive number, got -1$",
        ),
        (
            "rungs:\n  - {rate_kbps: 10, width: 175, height: 144, fps: 5}\n",
            r"h\.yaml:2 \(rungs\[0\]\.width\): expected an even number \(4:2:0 chroma\), got 175",
        ),
        (
            "rungs:\n  - {rate_kbps: 10, width: 176.5, height: 144, fps: 5}\n",
            r"\(rungs\[0\]\.width\): expected a positive integer, got 176\.5",
        ),
        (
            "rungs:\n  - {rate_kbps: .nan, width: 176, height: 144, fps: 5}\n",
            r"\(rungs\[0\]\.rate_kbps\): expected a positive number, got nan",
        ),
        (
            "rungs:\n  - {rate_kbps: ten, width: 176, height: 144, fps: 5}\n",
            r"\(rungs\[0\]\.rate_kbps\): expected a positive number, got 'ten'",
        ),
        (
            "rungs:\n" + RUNG + "  - {rate_kbps: 20, width: 176, height: 144, fps: 5}\n",
            r"h\.yaml:3 \(rungs\[1\]\.rate_kbps\): expected more than the rung below \(20\), got 20",
        ),
        (
            "rungs:\n  - {rate: 20, width: 176, height: 144, fps: 5}\n",
            r"\(rungs\[0\]\): unknown key 'rate'; expected keys rate_kbps, width, height, fps",
        ),
        (
            "rungs:\n  - {rate_kbps: 20, width: 176, height: 144}\n",
            r"\(rungs\[0\]\): missing key 'fps'",
        ),
        (
            "rungs:\n  - {rate_kbps: 1.0e+15, width: 176, height: 144, fps: 5}\n",
            r"h\.yaml:2 \(rungs\[0\]\.rate_kbps\): 1e\+15 is above the maximum 1e\+06",
        ),
        (
            "rungs:\n  - {rate_kbps: 20, width: 100000, height: 144, fps: 5}\n",
            r"h\.yaml:2 \(rungs\[0\]\.width\): 100000 is above the maximum 4096",
        ),
        (
            "rungs:\n  - {rate_kbps: 20, width: 176, height: 144, fps: 1e6}\n",
            r"h\.yaml:2 \(rungs\[0\]\.fps\): 1e\+06 is above the maximum 120",
        ),
        ("rungs:\n  - 20\n", r"\(rungs\[0\]\): expected a mapping"),
        ("rungs: 20\n", r"h\.yaml:1 \(rungs\): expected a list of rungs, got 20"),
        ("rungs: []\n", r"h\.yaml:1 \(rungs\): expected at least one rung"),
        ("ladder: []\n", r"h\.yaml:1: unknown key 'ladder'; expected keys rungs, encoder"),
        ("- 1\n", r"h\.yaml:1: expected a mapping"),
        ("encoder: {}\n", r"missing key 'rungs'"),
        (
            "encoder:\n  preset: fastest\nrungs:\n" + RUNG,
            r"h\.yaml:2 \(encoder\.preset\): expected one of ultrafast, .*, got 'fastest'",
        ),
        (
            "encoder:\n  tune: film\nrungs:\n" + RUNG,
            r"h\.yaml:2 \(encoder\.tune\): expected tunes including 'zerolatency'",
        ),
        (
            "encoder:\n  vbv_frames: 0.5\nrungs:\n" + RUNG,
            r"h\.yaml:2 \(encoder\.vbv_frames\): expected at least 1, got 0\.5",
        ),
        (
            "encoder:\n  keyint: 10\nrungs:\n" + RUNG,
            r"h\.yaml:2 \(encoder\): unknown key 'keyint'",
        ),
        ("rungs: [\n", r"h\.yaml:\d+: invalid YAML"),
    ],
)
def test_ladder_errors_name_file_line_and_key(tmp_path, body, message):
    path = tmp_path / "h.yaml"
    path.write_text(body)
    with pytest.raises(ConfigError, match=message):
        load_ladder(path)


def test_missing_ladder_file(tmp_path):
    with pytest.raises(ConfigError, match=r"none\.yaml: no such file"):
        load_ladder(tmp_path / "none.yaml")


def test_dataclasses_validate_when_built_in_code():
    with pytest.raises(ConfigError, match="rung fps: expected a positive number"):
        Rung(20, 176, 144, 0)
    with pytest.raises(ConfigError, match=r"rungs\[1\]\.rate_kbps: expected more"):
        Ladder((Rung(20, 176, 144, 5), Rung(10, 176, 144, 5)))
    with pytest.raises(ConfigError, match="encoder preset"):
        EncoderSettings(preset="turbo")


values = st.one_of(
    st.integers(-5, 5000),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=4),
    st.booleans(),
    st.none(),
    st.lists(st.integers(), max_size=2),
)
rung = st.dictionaries(
    st.sampled_from(["rate_kbps", "width", "height", "fps", "extra"]), values, max_size=5
)


@settings(max_examples=150, deadline=None)
@given(st.lists(rung, max_size=4), st.booleans())
def test_any_ladder_file_loads_or_raises_config_error(tmp_path_factory, rungs, wrap):
    path = tmp_path_factory.mktemp("ladder") / "h.yaml"
    path.write_text(yaml.safe_dump({"rungs": rungs} if wrap else rungs))
    try:
        ladder = load_ladder(path)
    except ConfigError as err:
        assert str(err).startswith(str(path))
    else:
        assert all(r.width % 2 == 0 and r.fps > 0 for r in ladder.rungs)
        assert [r.rate_kbps for r in ladder.rungs] == sorted({r.rate_kbps for r in ladder.rungs})


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.floats(1, 5000),
            st.integers(8, 400).map(lambda v: v * 2),
            st.integers(8, 300).map(lambda v: v * 2),
            st.floats(0.5, 60),
        ),
        min_size=1,
        max_size=6,
        unique_by=lambda r: r[0],
    )
)
def test_valid_ladders_round_trip(tmp_path_factory, rows):
    rows = sorted(rows)
    path = tmp_path_factory.mktemp("ladder") / "h.yaml"
    keys = ("rate_kbps", "width", "height", "fps")
    path.write_text(yaml.safe_dump({"rungs": [dict(zip(keys, row, strict=True)) for row in rows]}))
    assert load_ladder(path).rungs == tuple(Rung(*row) for row in rows)


def test_open_span_reaches_every_rung_of_the_size():
    ladder = load_ladder()
    by_size = {(r.width, r.height): ladder.open_span(r) for r in ladder.rungs}
    # CIF: 256k at 12.5 frames/s asks 512k of an encoder opened at 25; 1200k is the top
    assert by_size[(352, 288)] == (25.0, 1200.0)
    assert by_size[(256, 208)] == (12.5, 128.0)
    fps, ceiling = by_size[(176, 144)]
    assert fps == 8.333333 and ceiling == 40.0
    lone = Rung(100, 64, 48, 10)
    assert ladder.open_span(lone) == (10.0, 100.0)
