"""The settings of uma's controller (`uma.control.UmaController`): one set for every link.

Units in the names: kbit/s, ms, bits; fractions in (0, 1]. What each one does is in the
controller's docstring (`uma/control/controller.py`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

__all__ = ["UmaSettings", "DEFAULT_PRIORS_KBPS"]

# What each technology's downlink is expected to carry at most, as a prior (kbit/s).
DEFAULT_PRIORS_KBPS: Mapping[str, float] = MappingProxyType(
    {"GSM": 9.6, "GPRS": 40.0, "EDGE": 200.0, "3G": 2000.0, "UMTS": 2000.0}
)


@dataclass(frozen=True)
class UmaSettings:
    """uma's controller's tuning, checked when made (a bad value raises naming it)."""

    initial_kbps: float = 300.0
    min_kbps: float = 5.0
    max_kbps: float = 20_000.0
    headroom: float = 0.85
    capacity_tau_ms: float = 300.0
    queue_target_ms: float = 60.0
    queue_low_ms: float = 20.0
    drain_ms: float = 500.0
    beta: float = 0.85
    alr_fraction: float = 0.7
    probe_interval_ms: float = 1000.0
    probe_packets: int = 5
    probe_ms: float = 50.0
    probe_weight: float = 0.1
    probe_min_bits: int = 60 * 8  # 40 bytes of headers and a little padding
    packet_bits: int = 1200 * 8
    silence_ms: float = 250.0
    pause_ms: float = 150.0
    overdue_ms: float = 50.0
    received_tau_ms: float = 500.0
    skip_budget_ms: float = 300.0
    max_skip_ms: float = 1000.0
    silence_factor: float = 0.25
    recover_after_silence: bool = False
    recover_fraction: float = 0.85
    recover_window_ms: float = 5000.0
    overdue_in_any_report: bool = False
    no_probe_while_owed: bool = False
    no_probe_into_silence: bool = False
    fixed_due_time: bool = True
    no_probe_while_paused: bool = True
    take_queued_drop: bool = False
    bounded_queued_drop: bool = False
    queued_drop_floor: float = 0.5
    skip_limit_by_received: bool = True
    judge_silence: bool = False
    judge_window_ms: float = 1500.0
    judge_fraction: float = 1.0
    queue_from_owed: bool = True
    priors_kbps: Mapping[str, float] = field(default_factory=lambda: DEFAULT_PRIORS_KBPS)

    def __post_init__(self) -> None:
        if not 0 < self.min_kbps <= self.initial_kbps <= self.max_kbps:
            raise ValueError(
                "UmaSettings: expected 0 < min_kbps <= initial_kbps <= max_kbps, got "
                f"{self.min_kbps}, {self.initial_kbps}, {self.max_kbps}"
            )
        for name in (
            "headroom",
            "beta",
            "alr_fraction",
            "silence_factor",
            "probe_weight",
            "recover_fraction",
            "queued_drop_floor",
            "judge_fraction",
        ):
            if not 0 < getattr(self, name) <= 1:
                raise ValueError(
                    f"UmaSettings.{name}: expected in (0, 1], got {getattr(self, name)}"
                )
        for name in (
            "capacity_tau_ms",
            "drain_ms",
            "probe_interval_ms",
            "silence_ms",
            "received_tau_ms",
            "judge_window_ms",
        ):
            if not getattr(self, name) > 0:
                raise ValueError(f"UmaSettings.{name}: expected > 0, got {getattr(self, name)}")
        if self.probe_packets < 2:
            raise ValueError(f"UmaSettings.probe_packets: expected >= 2, got {self.probe_packets}")
