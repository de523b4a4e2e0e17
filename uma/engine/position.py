"""Which operating point the engine is on: the policies' choice, switches and fall-backs.

Units: times in seconds, rates in kbit/s.

The rate policy chooses a rung of the rate ladder; with switching on, the switching policy
chooses between that ladder and the model codec (`uma.engine.switching`). Moving between
families is a `codec_switch`, within the ladder a `rung_switch`; a failure falls back (a region
codec that found no face: the lowest full-frame rung, the region rungs blocked for their
section's `retry_ms`; the model codec: the lowest allowed rung), and the next frame sent
starts the new stream.
"""

from __future__ import annotations

from collections.abc import Callable

from uma.codecs import Role, spec
from uma.engine.ladder import Ladder
from uma.engine.policy import PolicyView
from uma.engine.records import EngineEvent, Tally
from uma.engine.switching import Switcher

__all__ = ["Position"]


class Position:
    """The point in use (`rung`), when it last changed, and whether a new stream is due."""

    def __init__(self, config, points, *, ladder: Ladder, switcher: Switcher, policy, rung: int):
        self.config, self.points, self.ladder, self.switcher = config, points, ladder, switcher
        self.policy = policy
        self.rung = rung
        self.switched_between = False  # the next frame sent starts a new stream
        self.codec_since_s = self.last_switch_s = 0.0
        self.cut_s = float("-inf")  # the last silence cut of the estimate
        switching = config.switching
        oracle_ahead = switching.policy == "oracle"
        self.lookahead_s = switching.oracle_lookahead_ms / 1000.0 if oracle_ahead else None

    def choose(
        self, now_s: float, *, estimate_kbps: float, capacity_kbps: float | None,
        budget_kbps: float, lowest_kbps: Callable[[float, float], float] | None,
        cut: bool = False,
    ) -> tuple[int, int | None, list]:  # fmt: skip
        """The point to be on, the model point to start initialising now (or None), and the
        actions the choice caused; `lowest_kbps(start_s, end_s)` the oracle's look ahead;
        `cut`: the estimate was cut for a silence just now."""
        config = self.config
        self.cut_s = now_s if cut else self.cut_s
        view = PolicyView(
            now_s=now_s, points=self.points, current=self.rung, last_switch_s=self.last_switch_s,
            estimate_kbps=estimate_kbps, safety=config.safety,
            up_hold_s=config.up_hold_ms / 1000.0, capacity_kbps=capacity_kbps,
            fixed_rung=config.fixed_rung, ladder=self.ladder.allowed(now_s),
            climb=config.climb,
        )  # fmt: skip
        if config.switching.policy == "none":
            return self.policy(view), None, []
        ahead = None
        if self.lookahead_s is not None and lowest_kbps is not None:
            ahead = config.safety * lowest_kbps(now_s, now_s + self.lookahead_s)
        return self.switcher.choose(
            view, self.policy, since_s=self.codec_since_s, budget_kbps=budget_kbps,
            budget_ahead_kbps=ahead, cut_s=self.cut_s,
        )  # fmt: skip

    def switch_to(self, wanted: int, now_s: float, kind: str, estimate_kbps: float) -> list:
        old, new = self.points[self.rung], self.points[wanted]
        estimate = f"estimate {estimate_kbps:.1f} kbps"
        # Region and full-frame rungs are one rate ladder: moving between them is a rung
        # switch; a codec switch is between that ladder and the model codec.
        if self.ladder.family(self.rung) != self.ladder.family(wanted):
            self.codec_since_s = now_s
            event = EngineEvent(now_s, "codec_switch", f"{old.codec}->{new.codec} {estimate}")
        else:
            event = EngineEvent(now_s, kind, f"{self.rung}->{wanted} {estimate}")
        self.rung, self.last_switch_s = wanted, now_s
        return [event]

    def fall_back(self, lowest: int, now_s: float, estimate_kbps: float) -> list:
        if self.rung == lowest:
            return []
        self.switched_between = True  # the next frame sent starts the new stream
        return self.switch_to(lowest, now_s, "fallback", estimate_kbps)

    def coder_failed(self, reason: str, now_s: float, estimate_kbps: float) -> list:
        """The coder could not code the picture: a region codec found no face, or the model
        codec lost it (`Switcher.model` says whether it was on)."""
        codec = spec(self.points[self.rung].codec)
        if codec.role is not Role.REGION:
            actions = self.switcher.model.track_failed(reason, now_s)
            lowest = self.ladder.allowed(now_s)[0]
            return actions + self.fall_back(lowest, now_s, estimate_kbps) if actions else []
        section = codec.config_section
        self.ladder.block_regions(now_s + getattr(self.config, section).retry_ms / 1000.0)
        detail = f"{reason}; lowest full-frame rung"
        out = [Tally(f"{section}_failures"), EngineEvent(now_s, f"{section}_failed", detail)]
        return out + self.fall_back(self.ladder.full_frame[0], now_s, estimate_kbps)
