"""A frame's walk through the engine: at most three calls per source frame.

Counted with a proxy around the engine of a short run: every call into it is recorded with the
source frame whose decision it follows. The engine process calls `on_frame` (the decision),
`on_coded` (what coding came to) and `on_sent` (the unit, once coded) for a frame, in that
order, before the next frame's `on_frame`; receiver reports, keyframe requests, the end of an
initialisation and the pacer's wake-ups are not per frame and are counted apart. The run uses
the pacer, the model codec and its refresh, so every kind of call happens.
"""

from collections import Counter

import pytest

import uma.sim.world as world_module
from uma.config.scenario import Scenario
from uma.engine import UmaEngine
from uma.sim import run_scenario

PER_FRAME = ("on_frame", "on_coded", "on_sent")


class CountingEngine(UmaEngine):
    """The engine, with each call kept as (method, frame the world was on)."""

    calls: list[tuple[str, int]] = []

    def __getattribute__(self, name):
        attr = super().__getattribute__(name)
        if not name.startswith("on_") or not callable(attr):
            return attr
        calls = type(self).calls

        def counted(*args, **kwargs):
            frame = args[0] if name == "on_frame" else (calls[-1][1] if calls else -1)
            calls.append((name, frame))
            return attr(*args, **kwargs)

        return counted


@pytest.fixture(scope="module")
def calls():
    CountingEngine.calls = []
    patch = pytest.MonkeyPatch()
    patch.setattr(world_module, "UmaEngine", CountingEngine)
    try:
        result = run_scenario(
            Scenario.model_validate(
                {
                    "name": "walk",
                    "seed": 3,
                    "source": {"kind": "talking-head", "width": 176, "height": 144, "fps": 25},
                    "route": [
                        {"technology": "WLAN", "duration_s": 1.0},
                        {"technology": "GPRS", "duration_s": 3.5},
                    ],
                    "engine": {
                        "policy": "oracle",
                        "switching": {"policy": "threshold", "min_dwell_ms": 500},
                        "mbc": {"refresh": {"enabled": True}},
                        "pacer": {"enabled": True},
                    },
                    "metrics": {"ssim": False, "psnr": False, "workers": 0},
                }
            )
        )
    finally:
        patch.undo()
    return result, CountingEngine.calls


def test_at_most_three_engine_calls_per_source_frame(calls):
    result, kept = calls
    per_frame = Counter(frame for name, frame in kept if name in PER_FRAME)
    frames = round(result.duration_s * result.fps)
    assert sorted(per_frame) == list(range(frames))  # every frame decided, nothing before
    assert max(per_frame.values()) <= 3
    # The walk happened: frames were coded and sent, the model codec ran with its refresh.
    kinds = Counter(name for name, _ in kept)
    assert kinds["on_frame"] == frames and kinds["on_coded"] > 0 and kinds["on_sent"] > 0
    assert kinds["on_pace"] > 0 and kinds["on_report"] > 0
    assert "mbc" in set(result.log["codec"])


def test_the_walk_is_in_order(calls):
    _, kept = calls
    walk = [name for name, _ in kept if name in PER_FRAME]
    for before, after in zip(walk, walk[1:], strict=False):
        assert (before, after) in {
            ("on_frame", "on_frame"),  # not sent: the decision is the whole walk
            ("on_frame", "on_coded"),
            ("on_coded", "on_sent"),
            ("on_sent", "on_frame"),
        }
