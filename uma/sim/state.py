"""What the processes of one run share: the `World`, wired by `uma.sim.world.run_scenario`.

Units: simulation time in seconds; sizes in bits.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import simpy

from uma.codecs import Role, spec
from uma.config.scenario import Scenario
from uma.engine.engine import UmaEngine
from uma.engine.points import OperatingPoint
from uma.metrics.framelog import FrameLog
from uma.sim.capacity import CapacitySchedule
from uma.sim.links import Downlink, FixedLink, LinkProps, deliver_later
from uma.sim.receiver import ReceiverState
from uma.sim.stats import ModelWork, SentBits

__all__ = ["FEEDBACK_BYTES", "World"]

# A report or keyframe request on the wire when the uplink's capacity is measured: the
# headers and a transport-wide feedback message of one report interval's packets.
FEEDBACK_BYTES = 100


@dataclass
class World:
    """Everything the processes share.

    Its tallies (`uma.sim.stats`): the bits offered to the downlink by kind (`sent`), the
    model codec's work (`model`) and the refresh's engine compute (`refresh`, whose receiver
    side the receiver keeps).
    """

    env: simpy.Environment
    scenario: Scenario
    frames: int
    fps: float
    source_iter: Any
    ladder: Any
    engine: UmaEngine
    capacity: CapacitySchedule
    uplink: FixedLink
    downlink: Downlink
    receiver: ReceiverState
    link_props: Callable[[str], LinkProps]
    feedback_rng: np.random.Generator
    log: FrameLog
    codec: Any  # uma.sim.codecs.CodecChain: the real encoders and decoders
    quality: Any  # uma.sim.quality.QualityMeter
    progress: Callable[[int, int], None] | None = None
    source_frames: dict[int, np.ndarray] = field(default_factory=dict)
    inbox: simpy.Store | None = None
    next_unit_seq: int = 0
    feedback_lost: int = 0
    on_display: Callable | None = None  # (index, source, shown, picture): `uma report --video`
    faults: Any = None  # uma.sim.faults.Faults: feedback silence
    playout: Any = None  # uma.sim.playout: FixedPlayout or AdaptivePlayout (None: fixed)
    points: tuple[OperatingPoint, ...] = ()  # the engine's operating points
    init_us_per_evaluation: float = 0.0  # the model codec's initialisation cost
    face_boxes: list = field(default_factory=list)  # per source frame read: `uma.face.Box` | None
    sent: SentBits = field(default_factory=SentBits)
    model: ModelWork = field(default_factory=ModelWork)
    pacer_kick: simpy.Event | None = None  # wakes `pacer_process` when a unit is queued
    next_refresh_seq: int = 0  # the model-aided refresh's units are numbered apart
    # The uplink's measured capacity (`feedback.trace`; None: the downlink's stands for it)
    # and when it has sent the reports before (they leave in order).
    feedback_capacity: CapacitySchedule | None = None
    feedback_free_s: float = 0.0

    def kick_pacer(self) -> None:
        """Something was queued in the engine's pacer: let it look now."""
        if self.pacer_kick is not None and not self.pacer_kick.triggered:
            self.pacer_kick.succeed()

    def init_compute_s(self, evaluations: int) -> float:
        """Modelled seconds of one model-codec initialisation that cost `evaluations`."""
        return self.init_us_per_evaluation * evaluations / 1e6

    def compute_s(self, point: OperatingPoint, out) -> float:
        """Modelled engine seconds for coding one picture at `point` (`out`: its `Coded`).

        A model codec whose tracker lost the face and initialised again pays for that as an
        initialisation; its compute is also tallied in `model`."""
        compute_s = point.compute_s(out.evaluations)
        model = spec(point.codec).role is Role.MODEL
        if model and (out.reinitialised or out.failure):
            compute_s = point.compute_s(0) + self.init_compute_s(out.evaluations)
        if model:
            self.model.compute_s += compute_s
        return compute_s

    def send_feedback(self, item, handler: Callable) -> None:
        """Carry a report or request over the mobile uplink; lost in an outage or at random.

        Without a measured uplink, an instant of zero downlink capacity is an outage both ways;
        with one (`feedback_capacity`), the report waits for the uplink's own capacity behind
        the reports before it, lost only if that never comes."""
        now_s = self.env.now
        if self.faults is not None and self.faults.feedback_silent(now_s):
            self.feedback_lost += 1
            return
        sent_s = now_s
        if self.feedback_capacity is None:
            if self.capacity.rate_kbps_at(now_s) <= 0.0:
                self.feedback_lost += 1
                return
        else:
            start_s = max(now_s, self.feedback_free_s)
            sent_s = self.feedback_capacity.finish_time_s(start_s, 8 * FEEDBACK_BYTES)
            if not math.isfinite(sent_s):
                self.feedback_lost += 1
                return
            self.feedback_free_s = sent_s
        props = self.link_props(self.capacity.technology_at(now_s))
        if self.feedback_rng.random() < props.loss_rate:
            self.feedback_lost += 1
            return
        delay_s = sent_s - now_s + props.delay_s
        deliver_later(self.env, delay_s, lambda value: handler(value, self.env.now), item)
