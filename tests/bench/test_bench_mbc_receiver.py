"""`uma bench mbc`'s receiver draws only what a receiver draws: the decoded sets (its drawing is
timed; the scores' own drawings go to a twin, so they never change what it keeps)."""

from __future__ import annotations

import numpy as np


def test_the_timed_receiver_draws_only_decoded_sets(monkeypatch) -> None:
    import uma.bench.mbc as bench
    from uma.bench.mbc_clips import talking_head_clip
    from uma.mbc.scene_render import SceneRenderer

    made, tracked, drawn = {}, [], []
    renderers, track, render = bench._renderers, bench._track, SceneRenderer.render

    def kept_renderers(*args, **kwargs):
        out = renderers(*args, **kwargs)
        made["receiver"], made["scorer"] = out[3], out[4]
        return out

    def kept_track(*args, **kwargs):
        out = track(*args, **kwargs)
        tracked.extend(np.asarray(r.params, np.float64).copy() for r in out if r)
        return out

    def recorded(self, params, *args, **kwargs):
        if self is made.get("receiver"):
            drawn.append(np.asarray(params, np.float64).copy())
        return render(self, params, *args, **kwargs)

    monkeypatch.setattr(bench, "_renderers", kept_renderers)
    monkeypatch.setattr(bench, "_track", kept_track)
    monkeypatch.setattr(SceneRenderer, "render", recorded)
    clip = talking_head_clip(6)
    out = bench.run_clip(clip, refresh={})
    assert made["receiver"] is not made["scorer"]
    assert len(drawn) == out["frames"]  # one drawing a decoded frame, nothing else
    for params in drawn:  # a decoded set, never the tracker's own (unquantised) one
        assert not any(np.array_equal(params, own) for own in tracked[1:])
