"""The engine's one send path (`uma.engine.sending`): cut, queued, numbered in one place."""

import ast
from pathlib import Path

from uma.config.engine import PacerConfig
from uma.engine import SendPacket, WakePacer
from uma.engine.sending import HEADER_BYTES, Outbox, packet_sizes_bits, padding_sizes_bits

ENGINE = Path(__file__).parents[2] / "uma" / "engine"


def test_sequence_numbers_are_given_in_one_module():
    """Only `uma/engine/sending.py` hands out sequence numbers (`InFlight.on_sent`)."""
    callers = set()
    for path in ENGINE.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            call = isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
            if call and node.func.attr == "on_sent" and "inflight" in ast.unparse(node.func.value):
                callers.add(path.name)
    assert callers == {"sending.py"}


def test_without_the_pacer_everything_leaves_at_once_numbered_in_order():
    outbox = Outbox(PacerConfig(enabled=False), payload_bytes=1000, source_fps=25.0)
    sent, bits = outbox.unit("u0", 2500, frames=(0,), keyframe=True, priority=False, now_s=0.0)
    assert [p.seq for p in sent] == [0, 1, 2] and [p.index for p in sent] == [0, 1, 2]
    assert bits == sum(packet_sizes_bits(2500, payload_bytes=1000))
    assert all(p.kind == "video" and p.payload == "u0" and p.count == 3 for p in sent)
    padding = outbox.padding(8 * 1500, 0.0)
    assert [p.seq for p in padding] == [3, 4] and {p.kind for p in padding} == {"padding"}
    chunks = outbox.number([SendPacket("description", None, 0, 2, 8000, -1)], 0.0)
    assert chunks[0].seq == 5 and outbox.queued_bits == 0
    assert outbox.inflight.outstanding_bits == bits + 8 * 1500 + 8000


def test_with_the_pacer_units_wait_and_leave_numbered_when_released():
    outbox = Outbox(PacerConfig(enabled=True), payload_bytes=1000, source_fps=25.0)
    sent, _ = outbox.unit("u0", 2500, frames=(0,), keyframe=True, priority=False, now_s=0.0)
    assert sent == [WakePacer()] and outbox.queued_bits > 0
    released, _ = outbox.release(0.0, 10_000.0, network_delay_s=0.0, hold=False)
    assert [p.seq for p in released] == list(range(len(released))) and released


def test_packet_sizes_carry_the_headers():
    assert packet_sizes_bits(2500, payload_bytes=1000) == [
        8 * (1000 + HEADER_BYTES), 8 * (1000 + HEADER_BYTES), 8 * (500 + HEADER_BYTES),
    ]  # fmt: skip
    assert packet_sizes_bits(0, payload_bytes=1000) == [8 * (1 + HEADER_BYTES)]
    assert padding_sizes_bits(8 * HEADER_BYTES, payload_bytes=1000) == []
