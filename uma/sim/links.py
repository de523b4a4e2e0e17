"""The SimPy links: the trace-driven downlink bottleneck, the good uplink, the feedback path.

Units: simulation time in seconds; sizes in bits and bytes as named; delays in ms in configs.

Downlink: a drop-tail queue limited in bytes (the packet being sent still occupies it), served at
the capacity of a `CapacitySchedule`, then a propagation delay and a random loss that depend on
the technology in use when the packet leaves. Delivery stays in order: a packet never overtakes
one sent before it, even when a handover shortens the propagation delay (unless the scenario
injects reordering, `uma.sim.faults`).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import simpy

from uma.sim.capacity import CapacitySchedule
from uma.sim.packets import Packet

__all__ = ["LinkProps", "Downlink", "downlink_process", "LinkStats", "FixedLink"]


@dataclass(frozen=True)
class LinkProps:
    """Propagation delay and random loss of one technology."""

    delay_s: float
    loss_rate: float


@dataclass
class LinkStats:
    packets_sent: int = 0
    packets_dropped_queue: int = 0
    packets_lost_random: int = 0
    packets_lost_burst: int = 0
    packets_reordered: int = 0
    packets_delivered: int = 0
    bits_offered: int = 0
    bits_delivered: int = 0
    max_queue_bytes: int = 0
    # Still queued when the run ended (an outage that outlasts it): sent = dropped + lost +
    # delivered + queued at the end.
    packets_queued_at_end: int = 0


@dataclass
class Downlink:
    """State of the bottleneck; `downlink_process` serves it."""

    env: simpy.Environment
    capacity: CapacitySchedule
    queue_limit_bytes: int
    props: Callable[[str], LinkProps]
    rng: np.random.Generator
    deliver: Callable[[Packet], None]
    queue: deque = field(default_factory=deque)
    queued_bytes: int = 0
    last_delivery_s: float = 0.0
    stats: LinkStats = field(default_factory=LinkStats)
    wakeup: simpy.Event | None = None
    faults: Any = None  # uma.sim.faults.Faults: loss bursts and reordering

    def offer(self, packet: Packet) -> bool:
        """Enqueue `packet`, or drop it when the queue has no room (drop-tail)."""
        size_bytes = packet.size_bits // 8
        self.stats.packets_sent += 1
        self.stats.bits_offered += packet.size_bits
        if self.queued_bytes + size_bytes > self.queue_limit_bytes:
            self.stats.packets_dropped_queue += 1
            return False
        self.queue.append(packet)
        self.queued_bytes += size_bytes
        self.stats.max_queue_bytes = max(self.stats.max_queue_bytes, self.queued_bytes)
        if self.wakeup is not None and not self.wakeup.triggered:
            self.wakeup.succeed()
        return True


def downlink_process(env: simpy.Environment, link: Downlink):
    """Serve the queue one packet at a time at the trace's capacity."""
    while True:
        if not link.queue:
            link.wakeup = env.event()
            yield link.wakeup
            link.wakeup = None
        packet = link.queue[0]
        finish_s = link.capacity.finish_time_s(env.now, packet.size_bits)
        if math.isinf(finish_s):
            return  # capacity never returns: the packet and those behind it stay queued
        yield env.timeout(finish_s - env.now)
        link.queue.popleft()
        link.queued_bytes -= packet.size_bits // 8
        props = link.props(link.capacity.technology_at(env.now))
        if link.rng.random() < props.loss_rate:
            link.stats.packets_lost_random += 1
            continue
        if link.faults is not None and link.faults.burst_lost():
            link.stats.packets_lost_burst += 1
            continue
        held_s = link.faults.reorder_delay_s() if link.faults is not None else 0.0
        if held_s > 0.0:
            # Held back in the network: later packets overtake it (the in-order floor is not raised).
            arrive_s = env.now + props.delay_s + held_s
            link.stats.packets_reordered += 1
        else:
            arrive_s = max(env.now + props.delay_s, link.last_delivery_s)
            link.last_delivery_s = arrive_s
        link.stats.packets_delivered += 1
        link.stats.bits_delivered += packet.size_bits
        _deliver_at(env, arrive_s, link.deliver, packet)


def _deliver_at(env: simpy.Environment, when_s: float, deliver: Callable, item) -> None:
    event = env.timeout(when_s - env.now, value=item)
    event.callbacks.append(lambda ev: deliver(ev.value))


@dataclass
class FixedLink:
    """A FIFO link of fixed rate and delay, without loss: the sender-to-engine path."""

    env: simpy.Environment
    rate_bps: float
    delay_s: float
    busy_until_s: float = 0.0

    def send(self, size_bits: int, item, deliver: Callable) -> float:
        """Serialise `item` after those before it, deliver it after the delay; returns arrival."""
        start_s = max(self.env.now, self.busy_until_s)
        self.busy_until_s = start_s + size_bits / self.rate_bps
        arrive_s = self.busy_until_s + self.delay_s
        _deliver_at(self.env, arrive_s, deliver, item)
        return arrive_s


def deliver_later(env: simpy.Environment, delay_s: float, deliver: Callable, item) -> None:
    """Call `deliver(item)` after `delay_s` of simulated time."""
    _deliver_at(env, env.now + delay_s, deliver, item)
