"""`engine.mbc`'s light, ring and refresh keys: defaults, read, and bad values named."""

import pytest

from uma.config import load_scenario
from uma.errors import ConfigError

MINIMAL = """\
name: demo
route:
  - technology: WLAN
    duration_s: 10
"""


def _load(tmp_path, mbc: str):
    path = tmp_path / "s.yaml"
    path.write_text(MINIMAL + "engine:\n  mbc:\n" + mbc)
    return load_scenario(path).engine.mbc


def test_defaults_keep_the_renderer_as_it_was_and_refresh_off(tmp_path):
    mbc = _load(tmp_path, "    light: true\n")
    assert mbc.light is True and mbc.light_ms == 1.5
    assert (mbc.far_ring_head_radii, mbc.head_ring_outlines) == (1.6, 1.4)
    assert mbc.refresh.enabled is False and mbc.refresh.face == "recent"


def test_keys_are_read(tmp_path):
    mbc = _load(
        tmp_path,
        "    light: false\n    far_ring_head_radii: 2.0\n"
        "    refresh: {enabled: true, max_frame_bits: 24000, min_interval_ms: 500,"
        " max_interval_ms: 2000, face: description}\n",
    )
    assert mbc.light is False and mbc.far_ring_head_radii == 2.0
    refresh = mbc.refresh
    assert refresh.enabled and refresh.max_frame_bits == 24000 and refresh.face == "description"
    assert (refresh.min_interval_ms, refresh.max_interval_ms) == (500, 2000)


def test_the_retired_scale_key_is_refused(tmp_path):
    # the refresh codes the face box at half size since issue 27; `scale` no longer applies
    with pytest.raises(ConfigError, match=r"engine\.mbc\.refresh\.scale"):
        _load(tmp_path, "    refresh: {scale: 0.5}\n")


@pytest.mark.parametrize(
    "mbc, where",
    [
        ("    far_ring_head_radii: 1.0\n", r"engine\.mbc\.far_ring_head_radii"),
        ("    light: maybe\n", r"engine\.mbc\.light"),
        ("    refresh: {face: mouth}\n", r"engine\.mbc\.refresh\.face"),
        ("    refresh: {share: 1.5}\n", r"engine\.mbc\.refresh\.share"),
        ("    refresh: {min_frame_bits: 10}\n", r"engine\.mbc\.refresh\.min_frame_bits"),
        ("    refresh: {min_frame_bits: 9000, max_frame_bits: 8000}\n", r"engine\.mbc\.refresh"),
        ("    refresh: {min_interval_ms: 3000, max_interval_ms: 1000}\n", r"engine\.mbc\.refresh"),
        ("    refresh: {intervall_ms: 3000}\n", r"engine\.mbc\.refresh\.intervall_ms"),
    ],
)
def test_bad_values_name_their_key(tmp_path, mbc, where):
    with pytest.raises(ConfigError, match=where):
        _load(tmp_path, mbc)


def test_intra_period_is_read_and_must_cover_a_packet(tmp_path):
    assert _load(tmp_path, "    light: true\n").intra_period_frames == 4  # every packet
    assert _load(tmp_path, "    intra_period_frames: 8\n").intra_period_frames == 8
    with pytest.raises(ConfigError, match=r"intra_period_frames \(2\) must be at least"):
        _load(tmp_path, "    intra_period_frames: 2\n")
