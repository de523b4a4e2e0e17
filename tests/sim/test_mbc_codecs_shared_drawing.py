"""The simulation's engine draws its mirror once a frame where the refresh's judge reads it:
the block map's drawing is then whole and kept, and the judge is handed it."""

import numpy as np
import pytest

from uma.config.codecs import MbcConfig, RefreshConfig

SIZE = (176, 144)


@pytest.fixture(scope="module")
def head():
    import cv2

    from uma.face.talking_head import Motion, TalkingHeadSource

    source = TalkingHeadSource(*SIZE, seed=2, motion=Motion(noise_std=0.0))
    frames = [cv2.cvtColor(source.render_bgr(i), cv2.COLOR_BGR2YUV_I420) for i in range(0, 8, 2)]
    return source, frames


def _encoder(source, refresh: RefreshConfig):
    from uma.mbc import StreamConfig
    from uma.sim.mbc_codecs import MbcPointEncoder

    context = {
        "description": source.description, "source_size": SIZE, "fps": 25.0,
        "mbc": MbcConfig(refresh=refresh), "stream": StreamConfig(frames_per_packet=1),
    }  # fmt: skip
    return MbcPointEncoder(None, source_size=SIZE, source_fps=25.0, settings=None, context=context)


def _wholes(encoder, frames, monkeypatch) -> list[bool]:
    """`whole` as the encoder asks its map for each frame (its allowance kept full, so the
    map draws), the refresh of frame 1 taken after frame 1."""
    from uma.mbc.map_sender import MapSender

    asked = []
    changes = MapSender.changes

    def spied(self, *args, whole=False):
        asked.append(whole)
        self.stream_bits = 0.0  # the parameters' own bits left out: the map can spend
        return changes(self, *args, whole=whole)

    monkeypatch.setattr(MapSender, "changes", spied)
    assert encoder.initialise(frames[0], frame=0)
    for i, picture in enumerate(frames):
        encoder.encode(picture, intra=i == 0, frame=i)
        if i == 1:
            encoder.take_refresh(encoder.stream.decoded, picture, refresh_frame=1)
    return asked


def test_the_maps_drawing_is_whole_once_the_judge_reads_the_mirror(head, monkeypatch):
    source, frames = head
    config = RefreshConfig(enabled=True, preset="ultrafast", min_gain_db=0.5)
    encoder = _encoder(source, config)
    assert _wholes(encoder, frames, monkeypatch) == [False, False, True, True]
    # The judge's drawing of the last frame's set is the map's, handed out by the memo.
    values, units = encoder.stream.decoded, encoder.units
    hits = encoder.mirror._memo.hits
    params, light = units.split(values)
    kept, _ = encoder.mirror.render(params, light, units.body_of(values), luma_only=True)
    assert encoder.mirror._memo.hits == hits + 1
    encoder.mirror._memo.clear()  # the same set drawn afresh: the same luma
    drawn, _ = encoder.mirror.render(params, light, units.body_of(values), luma_only=True)
    height = SIZE[1]
    assert np.array_equal(kept[:height], drawn[:height])


def test_nothing_is_drawn_whole_without_a_refresh(head, monkeypatch):
    source, frames = head
    config = RefreshConfig(enabled=False)
    assert not any(_wholes(_encoder(source, config), frames, monkeypatch))
