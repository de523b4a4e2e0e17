"""The engine's refresh judge reads the engine's own view of what the receiver's model codec
draws over (`uma.sim.sent_view.SentView`: the units the engine released, decoded by decoders
of its own), never the receiver's state."""

from pathlib import Path

import numpy as np

from uma.codecs import model_names
from uma.config import load_scenario
from uma.sim import run_scenario
from uma.sim.codecs import CodecChain
from uma.sim.context import CodecContext
from uma.sim.packets import EncodedUnit
from uma.sim.sent_view import SentView

SCENARIO = Path(__file__).resolve().parents[1] / "baselines" / "refresh-gprs.yaml"


def _unit(codec: str, frame: int, keyframe: bool) -> EncodedUnit:
    return EncodedUnit(unit_seq=frame, frame=frame, codec=codec, rung=0, width=176, height=144,
                       keyframe=keyframe, data=b"")  # fmt: skip


def test_no_picture_off_the_model_codec_or_with_nothing_before_it():
    view = SentView(CodecContext())
    assert view.stretch_picture() is None
    view.released(_unit(model_names()[0], 0, True))  # nothing released before the stretch
    assert view.stretch_picture() is None
    view.released(_unit("h264", 1, True))  # a full-frame unit ends the stretch
    assert view.stretch_picture() is None


def test_the_judge_sees_the_receivers_picture_from_the_engines_own_units(monkeypatch):
    seen = []
    judge = CodecChain.engine_refresh

    def spy(self, picture, order):
        theirs = self.context.background if self.receiver.on_model else None
        seen.append((self.sent.stretch_picture(), theirs))
        return judge(self, picture, order)

    monkeypatch.setattr(CodecChain, "engine_refresh", spy)
    # The first 8 s: WLAN, then 5 s of GPRS on the model codec with its refreshes.
    run_scenario(load_scenario(SCENARIO).model_copy(update={"duration_s": 8.0}))
    both = [(mine, theirs) for mine, theirs in seen if theirs is not None]
    # Nothing is lost on this route: where the receiver has its picture, the engine's decode
    # of what it released is that picture to the byte.
    assert len(both) >= 5 and all(np.array_equal(mine, theirs) for mine, theirs in both)
    # The first refresh is judged while the model codec's first unit is still on its way: the
    # engine knows the picture before the receiver has decoded it.
    assert any(mine is not None and theirs is None for mine, theirs in seen)
