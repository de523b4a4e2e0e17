"""GCC's rate controllers: AIMD on the delay signal, the loss-based bound, probing.

Units: kbit/s, ms, fractions. From draft-ietf-rmcat-gcc-02 (sections 5.5 and 6) and libwebrtc's
documented design:

- **AIMD** (draft 5.5): states HOLD, INCREASE, DECREASE (`AimdState`), one transition table
  (`TRANSITIONS`): over-use -> DECREASE, under-use -> HOLD, normal -> INCREASE from HOLD or
  INCREASE, HOLD after a DECREASE. Decrease: 0.85 x the received rate. Increase:
  multiplicative (x 1.08 per second) while far from convergence, additive (one average packet
  per response time, rtt + 100 ms, at least 4 kbit/s per second) near it. Near means: the
  received rate lies within three standard deviations of the link capacity estimate, a
  moving average of the received rate at each decrease; above it the estimate is dropped and
  the increase is multiplicative again. An increase never takes the target above 1.5 x
  received + 10 kbit/s, nor does that bound lower a target already above it (a probe's
  result, libwebrtc's reading of the draft's bound: an application-limited sender, whose
  encoder cannot fill the estimate, keeps what its probe measured).
- **Loss** (draft 6): loss above 10 % -> A_s x (1 - 0.5 loss); below 2 % -> A_s x 1.05 per
  second, and without loss never below A_r (it binds only after losses); in between, hold.
  The target is min(A_r, A_s).
- **Probing** (libwebrtc): at start, clusters at 3x and 6x the initial rate; then, while the
  stream is application-limited (received well below the target), one at 2x the target every
  `alr_probe_ms`. A probe's measured rate (its train's dispersion) above the target raises it.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from uma.control.gcc_delay import Usage

__all__ = ["AimdState", "TRANSITIONS", "AimdController", "LossController", "GccRateSettings"]


class AimdState(enum.Enum):
    HOLD = "hold"
    INCREASE = "increase"
    DECREASE = "decrease"


# (state, signal) -> next state; every transition of the AIMD controller is here.
TRANSITIONS: dict[tuple[AimdState, Usage], AimdState] = {
    **{(state, Usage.OVER): AimdState.DECREASE for state in AimdState},
    **{(state, Usage.UNDER): AimdState.HOLD for state in AimdState},
    (AimdState.HOLD, Usage.NORMAL): AimdState.INCREASE,
    (AimdState.INCREASE, Usage.NORMAL): AimdState.INCREASE,
    (AimdState.DECREASE, Usage.NORMAL): AimdState.HOLD,
}


@dataclass(frozen=True)
class GccRateSettings:
    initial_kbps: float = 300.0
    min_kbps: float = 5.0
    max_kbps: float = 20_000.0
    beta: float = 0.85
    multiplicative_per_s: float = 1.08
    min_additive_kbps_per_s: float = 4.0
    packet_bits: int = 1200 * 8
    fps: float = 30.0
    loss_high: float = 0.10
    loss_low: float = 0.02
    loss_increase_per_s: float = 1.05

    def __post_init__(self) -> None:
        if not 0 < self.min_kbps <= self.initial_kbps <= self.max_kbps:
            raise ValueError(
                "GccRateSettings: expected 0 < min_kbps <= initial_kbps <= max_kbps, got "
                f"{self.min_kbps}, {self.initial_kbps}, {self.max_kbps}"
            )
        if not 0 < self.beta < 1:
            raise ValueError(f"GccRateSettings.beta: expected in (0, 1), got {self.beta}")
        if not 0 <= self.loss_low <= self.loss_high <= 1:
            raise ValueError(
                f"GccRateSettings: expected 0 <= loss_low <= loss_high <= 1, got "
                f"{self.loss_low}, {self.loss_high}"
            )


class _LinkCapacity:
    """A moving average and normalised variance of the received rate at decreases."""

    def __init__(self) -> None:
        self.mean_kbps: float | None = None
        self.variance = 0.4

    def on_decrease(self, received_kbps: float) -> None:
        if self.mean_kbps is None:
            self.mean_kbps = received_kbps
        else:
            self.mean_kbps = 0.95 * self.mean_kbps + 0.05 * received_kbps
        norm = max(self.mean_kbps, 1.0)
        error = self.mean_kbps - received_kbps
        self.variance = min(max(0.95 * self.variance + 0.05 * error * error / norm, 0.4), 2.5)

    def std_kbps(self) -> float:
        return math.sqrt(self.variance * (self.mean_kbps or 0.0))


class AimdController:
    """Usage signals in, the delay-based rate A_r out."""

    def __init__(self, settings: GccRateSettings | None = None) -> None:
        self.settings = settings or GccRateSettings()
        self.state = AimdState.HOLD
        self.target_kbps = self.settings.initial_kbps
        self.capacity = _LinkCapacity()
        self._last_ms: float | None = None

    def update(self, usage: Usage, received_kbps: float, now_ms: float, rtt_ms: float) -> float:
        s = self.settings
        dt_s = 0.0 if self._last_ms is None else max(0.0, now_ms - self._last_ms) / 1000.0
        self._last_ms = now_ms
        self.state = TRANSITIONS[self.state, usage]
        if self.state is AimdState.INCREASE:
            mean = self.capacity.mean_kbps
            if mean is not None and received_kbps > mean + 3.0 * self.capacity.std_kbps():
                self.capacity.mean_kbps = None  # the link grew: far from convergence again
            before = self.target_kbps
            if self.capacity.mean_kbps is not None:
                self.target_kbps += self._additive_kbps_per_s(rtt_ms) * dt_s
            else:
                self.target_kbps *= s.multiplicative_per_s ** min(dt_s, 1.0)
            # The increase stops at 1.5 x received + 10 (the draft's bound); it never takes the
            # target below where it was (a probe's result stays, as in libwebrtc).
            cap = 1.5 * received_kbps + 10.0
            if self.target_kbps > cap:
                self.target_kbps = max(min(before, self.target_kbps), cap)
        elif self.state is AimdState.DECREASE:
            decreased = s.beta * received_kbps
            self.target_kbps = min(self.target_kbps, decreased)
            self.capacity.on_decrease(received_kbps)
            self.state = AimdState.HOLD
        self.target_kbps = min(max(self.target_kbps, s.min_kbps), s.max_kbps)
        return self.target_kbps

    def raise_to(self, kbps: float) -> None:
        """A probe showed the link carries `kbps`: start from there."""
        self.target_kbps = min(max(self.target_kbps, kbps), self.settings.max_kbps)
        self.capacity.mean_kbps = None

    def _additive_kbps_per_s(self, rtt_ms: float) -> float:
        s = self.settings
        frame_bits = self.target_kbps * 1000.0 / s.fps
        packets = max(1, math.ceil(frame_bits / s.packet_bits))
        response_ms = rtt_ms + 100.0
        return max(s.min_additive_kbps_per_s, frame_bits / packets / response_ms)


class LossController:
    """Loss reports in, the loss-based bound A_s out."""

    def __init__(self, settings: GccRateSettings | None = None) -> None:
        self.settings = settings or GccRateSettings()
        self.bound_kbps = self.settings.initial_kbps
        self._last_ms: float | None = None

    def update(self, loss: float, now_ms: float, delay_based_kbps: float) -> float:
        s = self.settings
        dt_s = 0.0 if self._last_ms is None else max(0.0, now_ms - self._last_ms) / 1000.0
        self._last_ms = now_ms
        if loss > s.loss_high:
            self.bound_kbps *= 1.0 - 0.5 * loss
        elif loss < s.loss_low:
            # without loss the bound does not bind: it stays at least the delay-based rate
            self.bound_kbps = max(self.bound_kbps * s.loss_increase_per_s**dt_s, delay_based_kbps)
        self.bound_kbps = min(max(self.bound_kbps, s.min_kbps), s.max_kbps)
        return self.bound_kbps
