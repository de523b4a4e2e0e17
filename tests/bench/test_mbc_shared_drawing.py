"""One drawing of the engine's mirror a frame: the block map's drawing, whole on a frame the
refresh's judge reads, is the judge's (and the take's), and everything the engine and the
receiver do is the same to the bit as with each drawing its own."""

from __future__ import annotations

import numpy as np
import pytest

from tests.bench.test_bench_mbc_refresh import _Pose, head_clip  # noqa: F401 (a fixture)


@pytest.fixture(scope="module")
def cif_clip():
    """The talking head at CIF, 20 frames, with its body: the layered scene the bench draws."""
    import cv2

    from uma.bench.mbc import ClipSpec
    from uma.face.talking_head import TalkingHeadSource

    source = TalkingHeadSource(352, 288, seed=2)
    frames = [cv2.cvtColor(source.render_bgr(i), cv2.COLOR_BGR2YUV_I420) for i in range(0, 40, 2)]
    results = [_Pose(source.params_at(i)) for i in range(0, 40, 2)]
    return ClipSpec("head", frames, 25.0, source.description), results


def _run(clip_results, monkeypatch, *, shared: bool, body: bool):
    """The refresh display with the judge's drawing shared (or each drawing its own: the map
    always draws its window) and how many of the mirror's drawings the memo handed out."""
    import uma.bench.mbc_refresh as refreshing
    from uma.mbc.render_memo import RenderMemo
    from uma.mbc.stream import StreamConfig
    from uma.mbc.units import FaceUnits

    hits = []
    get = RenderMemo.get

    def counted(self, params, light, body):
        out = get(self, params, light, body)
        hits.append(out is not None)
        return out

    clip, results = clip_results
    units = FaceUnits.of(clip.description.model, clip.description.params, light=True, body=body)
    spec = refreshing.RefreshSpec(0, 12.5, region="face", face_scale=0.5)
    with monkeypatch.context() as patch:
        patch.setattr(RenderMemo, "get", counted)
        if not shared:
            patch.setattr(refreshing._Sender, "judges", lambda self, index: False)
        out = refreshing.refresh_display(clip, results, units, StreamConfig(), 0.5, spec)
    return *out, sum(hits)


@pytest.mark.parametrize("which", ["qcif", "cif_body"])
def test_the_shared_drawing_changes_no_pixel_and_no_decision(
    which,
    head_clip,  # noqa: F811
    cif_clip,
    monkeypatch,
) -> None:
    clip = head_clip if which == "qcif" else cif_clip
    body = which == "cif_body"
    shown, kbps, info, hits = _run(clip, monkeypatch, shared=True, body=body)
    old_shown, old_kbps, old_info, old_hits = _run(clip, monkeypatch, shared=False, body=body)
    assert len(shown) == len(old_shown)
    assert all(np.array_equal(a, b) for a, b in zip(shown, old_shown, strict=True))
    assert kbps == old_kbps
    for key in ("units", "adopted", "served", "params_kbps", "refresh_kbps"):
        assert info[key] == old_info[key], key
    assert info["units"] >= 4 and info["params_kbps"] > 0
    # The map drew (it spent bits), and the judge found its drawings in the memo.
    assert hits > old_hits, (hits, old_hits, info)
