"""What the engine's refresh calls do, apart from the dispatcher (`uma.engine.engine`): the
model-aided refresh's planner (`uma.engine.refresh`) wired to the engine's estimate, bits in
flight and receiver messages.

Units: times in seconds, rates in kbit/s, sizes in bits.
"""

from __future__ import annotations

from uma.codecs import Role, spec
from uma.engine.refresh import RefreshPlanner
from uma.engine.reports import KeyframeRequest, ReceiverReport

__all__ = [
    "build",
    "on_report",
    "keyframe_request",
    "on_refresh_coded",
    "on_refresh_pace",
    "released_bits",
    "decide",
]


def build(model_config, *, emit, counts: dict) -> RefreshPlanner | None:
    """The planner when the model codec's section enables the refresh, else None."""
    refresh = getattr(model_config, "refresh", None)
    if refresh is None or not refresh.enabled:
        return None
    return RefreshPlanner(refresh, emit=emit, counts=counts)


def on_report(engine, report: ReceiverReport) -> None:
    """A report says which refresh the receiver renders from."""
    if engine.refresh is not None:
        engine.refresh.on_ack(report.refresh_frame)


def keyframe_request(engine, request: KeyframeRequest, now_s: float) -> bool:
    """A request for an intra refresh (True: handled, it asks for no IDR)."""
    if not request.refresh:
        return False
    if engine.refresh is not None:
        engine.refresh.request_intra(now_s)
    return True


def on_refresh_coded(
    engine, packets: list[tuple[object, int]], now_s: float, *, intra: bool
) -> None:
    """The refresh a decision ordered was coded as `packets` ((packet, size_bits) each, not
    yet numbered; none: not sent): they wait in the engine for `on_refresh_pace`."""
    if engine.refresh is not None:
        engine.refresh.coded(packets, now_s, intra=intra)


def on_refresh_pace(engine, now_s: float) -> list[tuple[object, int]]:
    """The refresh packets that leave now, each with its sequence number (call every frame)."""
    if engine.refresh is None:
        return []
    out = engine.refresh.pace(now_s, queue_delay_ms=engine.estimator.queue_delay_ms)
    if not out:
        return []
    first_seq = engine.inflight.on_sent([bits for _, bits in out])
    return [(packet, first_seq + i) for i, (packet, _) in enumerate(out)]


def released_bits(engine) -> int:
    """Refresh bits that left since the last unit: they fill the probe's padding share."""
    return engine.refresh.take_released_bits() if engine.refresh is not None else 0


def decide(engine, frame: int, now_s: float, point, budget_kbps: float) -> dict:
    """The refresh fields of the decision to send `frame` at `point`: the refresh to code
    with it and the refresh the receiver now renders from (`FrameDecision` keywords)."""
    if engine.refresh is None:
        return {}
    # The oracle knows the capacity; the others spend no more than the link carried.
    oracle = engine.config.policy == "oracle"
    order = engine.refresh.on_frame(
        frame, now_s, on_model=spec(point.codec).role is Role.MODEL,
        budget_kbps=budget_kbps, model_kbps=point.rate_kbps,
        received_kbps=float("inf") if oracle else engine.estimator.received_kbps,
    )  # fmt: skip
    return {"refresh": order, "refresh_adopted": engine.refresh.take_adopted()}
