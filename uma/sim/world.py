"""Wire the world of one scenario and run it: the only function that knows every part.

Units: simulation time in seconds. Randomness: one `numpy.random.SeedSequence` from the
scenario's seed, split into independent streams for the route, downlink loss and feedback loss,
so the same seed and inputs give the same run, bit for bit.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import simpy

from uma.config.scenario import Scenario
from uma.control.delivery import DeliverySettings, DeliveryTracker
from uma.engine.decisions import EngineEvent
from uma.engine.engine import DescriptionPlan, UmaEngine
from uma.face.region import FaceBoxes
from uma.metrics.framelog import FrameLog
from uma.sim.capacity import CapacitySchedule
from uma.sim.codecs import CodecChain
from uma.sim.faults import Faults, fault_rng, with_outages
from uma.sim.links import Downlink, FixedLink, LinkProps, downlink_process
from uma.sim.packets import HEADER_BYTES
from uma.sim.playout import make_playout
from uma.sim.points import load_run_ladder, model_plan, operating_points
from uma.sim.processes import (
    display_process,
    engine_process,
    pacer_process,
    report_process,
    sender_process,
)
from uma.sim.quality import QualityMeter
from uma.sim.receiver import ReceiverState
from uma.sim.result import RunResult, collect_result
from uma.sim.sources import open_source
from uma.sim.state import World
from uma.sim.uplink import UplinkMemo

__all__ = ["RunResult", "run_scenario", "build_capacity", "feedback_capacity", "scenario_link"]


def build_capacity(scenario: Scenario, rng: np.random.Generator) -> CapacitySchedule:
    """The downlink capacity of the scenario's route, with its handover gaps."""
    from uma.traces import RouteSegment, build_route

    segments = [
        RouteSegment(
            technology=seg.technology,
            duration_s=seg.duration_s,
            trace=seg.trace,
            format=seg.format,
            offset_s=seg.offset_s,
            scale=seg.scale,
        )
        for seg in scenario.route
    ]
    trace = build_route(segments, rng=rng)
    return CapacitySchedule.from_trace(
        trace, handover_gap_s=scenario.downlink.handover_gap_ms / 1000.0
    )


def feedback_capacity(scenario: Scenario) -> CapacitySchedule | None:
    """The uplink's measured capacity (`feedback.trace`, read from the route's one segment's
    offset for as long, with the scenario's outage faults, which silence both ways), or None
    when the scenario gives none."""
    from uma.errors import TraceError
    from uma.traces import RouteSegment, build_route

    feedback = scenario.feedback
    if feedback.trace is None:
        return None
    segment = scenario.route[0]
    uplink = RouteSegment(
        technology=segment.technology, duration_s=segment.duration_s, trace=feedback.trace,
        format=feedback.format, offset_s=segment.offset_s,
    )  # fmt: skip
    try:  # a trace segment draws nothing from its generator (only generated rates do)
        trace = build_route([uplink], rng=np.random.default_rng(0))
    except TraceError as err:  # named by the key, not as the route's segment
        reason = str(err).split("): ", 1)[-1]
        raise TraceError(f"feedback.trace ({feedback.trace}): {reason}") from None
    return with_outages(CapacitySchedule.from_trace(trace), scenario.faults.outages)


def scenario_link(scenario: Scenario) -> tuple[CapacitySchedule, Callable[[str], float]]:
    """The downlink a run of `scenario` meets: its capacity (the route from the scenario's seed,
    handover gaps, outage faults) and the one-way delay in s of each technology."""
    route_rng = np.random.default_rng(np.random.SeedSequence(scenario.seed).spawn(3)[0])
    capacity = with_outages(build_capacity(scenario, route_rng), scenario.faults.outages)
    props = _link_props(scenario)
    return capacity, lambda technology: props(technology).delay_s


def _link_props(scenario: Scenario) -> Callable[[str], LinkProps]:
    from uma.traces import technology_defaults

    overrides = scenario.downlink.technologies
    cache: dict[str, LinkProps] = {}

    def props(technology: str) -> LinkProps:
        if technology not in cache:
            default = technology_defaults(technology)
            delay_ms, loss = default.delay_ms, default.loss_rate
            override = overrides.get(technology)
            if override is not None:
                delay_ms = override.delay_ms if override.delay_ms is not None else delay_ms
                loss = override.loss_rate if override.loss_rate is not None else loss
            cache[technology] = LinkProps(delay_s=delay_ms / 1000.0, loss_rate=loss)
        return cache[technology]

    return props


def _handover_events(capacity: CapacitySchedule, end_s: float) -> list[EngineEvent]:
    events = []
    techs = capacity.technologies
    for i in range(1, len(techs)):
        t_s = float(capacity.starts_s[i])
        if t_s < end_s and techs[i] != techs[i - 1] and techs[i] and techs[i - 1]:
            events.append(EngineEvent(t_s, "handover", f"{techs[i - 1]}->{techs[i]}"))
    return events


def coverage_map(scenario: Scenario) -> tuple[tuple[float, str], ...]:
    """The route's technology segments as a coverage map gives them: (start_s, technology)."""
    out, start_s = [], 0.0
    for segment in scenario.route:
        out.append((start_s, segment.technology))
        start_s += segment.duration_s
    return tuple(out)


def run_scenario(
    scenario: Scenario,
    *,
    progress: Callable[[int, int], None] | None = None,
    account: bool = False,
    source=None,
    on_display: Callable[[int, np.ndarray, int, np.ndarray | None], None] | None = None,
    uplink: UplinkMemo | None = None,
) -> RunResult:
    """Simulate `scenario`; `progress(done, total)` is told of each displayed frame.

    With `account`, the wall-clock seconds spent in codecs and quality metrics are summed for
    `uma bench sim`; they are measured, never used by the simulation. `source` replaces the
    scenario's frame source (a benchmark passes frames it prepared beforehand).
    `on_display(index, source, shown, picture)` sees each display instant's source frame and
    the picture shown (None before the first), for `uma report --video`. `uplink`: a memo of
    the sender's stream (`uma.sim.uplink`) to take it from and add to; results are the same.
    """
    _, loss_rng, feedback_rng = (
        np.random.default_rng(s) for s in np.random.SeedSequence(scenario.seed).spawn(3)
    )
    capacity, _ = scenario_link(scenario)
    faults = Faults(scenario.faults, rng=fault_rng(scenario.seed))
    ladder = load_run_ladder(scenario)
    source = source if source is not None else open_source(scenario.source, seed=scenario.seed)
    plan = model_plan(scenario, source)
    points = operating_points(scenario, ladder, source, with_model=plan.description is not None)
    fps = float(source.fps)
    frames = int(round(scenario.run_duration_s * fps))
    env = simpy.Environment()
    codec = CodecChain(
        scenario, ladder, points, width=source.width, height=source.height, fps=fps,
        account=account, description=plan.description, uplink=uplink,
    )  # fmt: skip
    quality = QualityMeter(scenario.metrics, width=source.width, height=source.height)
    face_boxes = FaceBoxes(source)
    engine = _engine(scenario, points, plan, fps)
    world = World(
        env=env, scenario=scenario, frames=frames, fps=fps,
        source_iter=face_boxes.wrap(source.frames()), ladder=ladder, engine=engine,
        capacity=capacity, uplink=FixedLink(
            env, scenario.uplink.rate_kbps * 1000.0, scenario.uplink.delay_ms / 1000.0
        ), downlink=None, receiver=None, link_props=_link_props(scenario),
        feedback_rng=feedback_rng, log=FrameLog(frames), codec=codec, quality=quality,
        progress=progress, inbox=simpy.Store(env), on_display=on_display,
        faults=faults if faults.active else None, playout=make_playout(scenario.receiver),
        init_us_per_evaluation=plan.init_us_per_evaluation, points=points,
        face_boxes=face_boxes.boxes, feedback_capacity=feedback_capacity(scenario),
    )  # fmt: skip
    _wire_receiver(world, loss_rng)
    _run(world)
    end_s = frames / fps
    outcome = engine.finish(end_s)
    events = sorted(_handover_events(capacity, end_s) + list(outcome.events), key=_time_s)
    return collect_result(
        world, outcome, events=tuple(events), source=source, description=plan.description,
        description_bytes=plan.description_bytes, duration_s=end_s,
    )  # fmt: skip


def _engine(scenario: Scenario, points, plan, fps: float) -> UmaEngine:
    """The engine on `points`, told what the world knows: the description to deliver, the
    coverage map, the packet size."""
    payload_bytes = scenario.downlink.packet_bytes
    return UmaEngine(
        scenario.engine, points=points, source_fps=fps, feedback=scenario.feedback,
        model_unavailable=plan.unavailable, coverage=coverage_map(scenario),
        description=DescriptionPlan(
            bits=8 * plan.description_bytes,
            chunks=-(-plan.description_bytes // payload_bytes),
            chunk_bits=8 * (payload_bytes + HEADER_BYTES),
        ),
        payload_bytes=payload_bytes,
    )  # fmt: skip


def _wire_receiver(world: World, loss_rng: np.random.Generator) -> None:
    """The receiver and the downlink that delivers to it; keyframe requests go back up
    through the world's feedback path."""
    scenario, env, codec, engine = world.scenario, world.env, world.codec, world.engine
    receiver = ReceiverState(
        log=world.log, decode=codec.receiver_decode,
        request_keyframe=lambda request: world.send_feedback(request, engine.on_keyframe_request),
        now=lambda: env.now, keyframe_retry_s=scenario.receiver.keyframe_retry_ms / 1000.0,
        base_delay_window_s=scenario.receiver.base_delay_window_s,
        technology=lambda: world.capacity.technology_at(env.now),
    )  # fmt: skip
    if codec.refresh is not None:
        receiver.decode_refresh = codec.receiver_refresh
        receiver.refresh_frame = codec.receiver_refresh_frame
    world.downlink = Downlink(
        env=env, capacity=world.capacity, queue_limit_bytes=scenario.downlink.queue_bytes,
        props=world.link_props, rng=loss_rng, deliver=receiver.on_packet, faults=world.faults,
    )  # fmt: skip
    playout, log = world.playout, world.log
    receiver.on_decoded = lambda frame, arrival_s: playout.on_decoded(
        log["capture_ms"][frame] / 1000.0, arrival_s
    )
    # The receiver's reports close the tracker's intervals (`flush`), never the tracker itself.
    receiver.delivery = DeliveryTracker(DeliverySettings(interval_ms=None))
    world.receiver = receiver


def _run(world: World) -> None:
    """Start the processes, run until the last frame is shown, and score what was shown."""
    env, log = world.env, world.log
    env.process(sender_process(env, world))
    env.process(engine_process(env, world))
    env.process(downlink_process(env, world.downlink))
    env.process(report_process(env, world))
    env.process(pacer_process(env, world))
    env.run(until=env.process(display_process(env, world)))
    for index, (psnr, similarity, face_psnr, face_ssim) in world.quality.finish().items():
        log["psnr_db"][index] = psnr
        log["ssim"][index] = similarity
        log["psnr_face_db"][index] = face_psnr
        log["ssim_face"][index] = face_ssim
    world.downlink.stats.packets_queued_at_end = len(world.downlink.queue)


def _time_s(event: EngineEvent) -> float:
    return event.time_s
