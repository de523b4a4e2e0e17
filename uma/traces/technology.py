"""Radio access technologies: link defaults (delay, loss) and a rate model that generates traces.

Units: rates in kbit/s, delays in ms (one way, engine to handset, core network included), loss as
a fraction of packets, times in seconds.

Typical figures behind the defaults (downlink, a moving user; one-way delay is half a measured
round trip time, RTT):
- GSM circuit-switched data: 9.6 kbit/s (TCH/F9.6; 14.4 where TCH/F14.4 is offered). The BTS alone
  adds up to 160-175 ms of RTT on a full-rate data channel (GSM 11.20 budget, Ericsson CME 20
  R6.1 manual); with interleaving, RLP and the interworking modem an end-to-end RTT of ~500 ms.
- GPRS: CS-2 gives 13.4 kbit/s a slot, 3-4 downlink slots give 20-54 kbit/s; Chakravorty,
  Cartwright and Pratt, "Practical experience with TCP over GPRS" (Globecom 2002): RTTs around
  and above 1000 ms, highly variable, losses rare. We take ~700 ms RTT (an unloaded cell).
- EDGE (EGPRS): MCS-5..9 give 22-59 kbit/s a slot, 100-200 kbit/s in practice on 4 slots
  (236.8 kbit/s at most); RTT 300-500 ms.
- 3G (UMTS R99 to HSPA): a few hundred kbit/s to 2 Mbit/s for a moving user; RTT 100-200 ms
  (Mohan, Kapoor, Mohanty, "Latency in HSPA data networks", Qualcomm 2011; Serrano et al.,
  "Latency in broad-band mobile networks", Vodafone).
- LTE: a few to tens of Mbit/s; RTT ~50 ms.
- 5G (NSA): tens to hundreds of Mbit/s; RTT 20-30 ms (Rohde & Schwarz public-network
  measurements, 2022).
- WLAN (802.11g/n at range): 1.5-20 Mbit/s; a few ms.
Random loss after link-layer retransmission (RLC acknowledged mode, 802.11 MAC retries) stays
well under 1 %. These are defaults only: a scenario overrides delay and loss per technology,
and measured traces give rates.

The rate model: log-rate follows an AR(1) process around log(mean_kbps) with stationary standard
deviation `sigma_log` and correlation `correlation_per_s` over one second (shadowing as the user
moves), clipped to [min_kbps, max_kbps]; on top, short outages to 0 kbit/s (cell edges,
tunnels) start at `fades_per_min` and last `fade_min_s` to `fade_max_s`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uma.errors import TraceError
from uma.traces.labels import LABELS, normalise_technology, technology_label
from uma.traces.trace import MAX_STEPS, Trace

__all__ = [
    "RateModel",
    "Technology",
    "TECHNOLOGIES",
    "technology_defaults",
    "normalise_technology",
    "generate",
]


def _check(name: str, value: float, low: float, high: float = math.inf) -> None:
    if not (math.isfinite(value) and low <= value <= high):
        raise TraceError(f"{name}: expected a number in [{low:g}, {high:g}], got {value!r}")


@dataclass(frozen=True)
class RateModel:
    """Log-normal AR(1) rate with clipping and short outages (see the module docstring)."""

    mean_kbps: float
    min_kbps: float
    max_kbps: float
    sigma_log: float
    correlation_per_s: float
    fades_per_min: float = 0.0
    fade_min_s: float = 1.0
    fade_max_s: float = 3.0

    def __post_init__(self) -> None:
        _check("mean_kbps", self.mean_kbps, 1e-9)
        _check("min_kbps", self.min_kbps, 0.0, self.mean_kbps)
        _check("max_kbps", self.max_kbps, self.mean_kbps)
        _check("sigma_log", self.sigma_log, 0.0)
        _check("correlation_per_s", self.correlation_per_s, 0.0, 1.0 - 1e-9)
        _check("fades_per_min", self.fades_per_min, 0.0)
        _check("fade_min_s", self.fade_min_s, 0.0)
        _check("fade_max_s", self.fade_max_s, self.fade_min_s)


@dataclass(frozen=True)
class Technology:
    """A technology's link defaults and rate model."""

    name: str
    delay_ms: float
    loss_rate: float
    rate: RateModel

    def __post_init__(self) -> None:
        _check(f"{self.name or 'unknown'} delay_ms", self.delay_ms, 0.0)
        _check(f"{self.name or 'unknown'} loss_rate", self.loss_rate, 0.0, 1.0)


def _technology(name: str, delay_ms: float, loss_rate: float, **rate: float) -> Technology:
    return Technology(name, delay_ms=delay_ms, loss_rate=loss_rate, rate=RateModel(**rate))


# Rates: GSM is a 9.6 kbit/s circuit that RLP retransmissions only slow down; GPRS up to CS-2 on
# 4 slots (53.6); EDGE up to MCS-9 on 4 slots (236.8); 3G from a loaded R99 cell to HSDPA for a
# moving user; LTE, 5G and WLAN wide and fast-fading. See the module docstring for the delays.
TECHNOLOGIES: dict[str, Technology] = {
    t.name: t
    for t in (
        _technology(
            "GSM", 250.0, 0.005, mean_kbps=9.6, min_kbps=4.8, max_kbps=9.6,
            sigma_log=0.15, correlation_per_s=0.9, fades_per_min=0.5,
        ),
        _technology(
            "GPRS", 350.0, 0.005, mean_kbps=35.0, min_kbps=8.0, max_kbps=53.6,
            sigma_log=0.35, correlation_per_s=0.85, fades_per_min=1.0,
        ),
        _technology(
            "EDGE", 200.0, 0.005, mean_kbps=150.0, min_kbps=40.0, max_kbps=236.8,
            sigma_log=0.35, correlation_per_s=0.85, fades_per_min=0.5,
        ),
        _technology(
            "3G", 60.0, 0.005, mean_kbps=800.0, min_kbps=150.0, max_kbps=2000.0,
            sigma_log=0.5, correlation_per_s=0.8, fades_per_min=0.2,
        ),
        _technology(
            "LTE", 25.0, 0.002, mean_kbps=15000.0, min_kbps=1000.0, max_kbps=50000.0,
            sigma_log=0.6, correlation_per_s=0.8,
        ),
        _technology(
            "5G", 15.0, 0.001, mean_kbps=80000.0, min_kbps=5000.0, max_kbps=300000.0,
            sigma_log=0.6, correlation_per_s=0.8,
        ),
        _technology(
            "WLAN", 5.0, 0.002, mean_kbps=8000.0, min_kbps=1500.0, max_kbps=20000.0,
            sigma_log=0.4, correlation_per_s=0.8,
        ),
    )
}  # fmt: skip

# For steps a trace leaves unlabelled: a neutral, lossless 50 ms link (no rate model is used).
_UNKNOWN = Technology("", 50.0, 0.0, RateModel(1000.0, 0.0, 1000.0, 0.0, 0.0))


def technology_defaults(name: str) -> Technology:
    """The defaults of `name` (aliases such as HSPA+ accepted); "" or "-" get a neutral link.

    A name that is no technology at all is a `TraceError`, so a typo never passes as "unknown".
    """
    label = technology_label(name)
    if label is None:
        raise TraceError(f"expected a technology among {', '.join(LABELS)} or '', got {name!r}")
    return TECHNOLOGIES.get(label, _UNKNOWN)


def generate(technology: str, duration_s: float, *, rng, step_s: float = 1.0) -> Trace:
    """A synthetic trace of `technology` from its rate model, reproducible from `rng`.

    `rng` is anything `np.random.default_rng` takes; a Generator is used (and advanced) in
    place, so a route drawing several segments from one Generator stays reproducible. Steps last
    `step_s`, the last one whatever remains of `duration_s`.
    """
    label = technology_label(technology)
    if not label:
        raise TraceError(
            f"cannot generate rates for technology {technology!r}; expected one of "
            f"{', '.join(LABELS)}"
        )
    if not (math.isfinite(duration_s) and duration_s > 0 and math.isfinite(step_s) and step_s > 0):
        raise TraceError(
            f"generate {label}: expected positive durations, got duration_s={duration_s!r}, "
            f"step_s={step_s!r}"
        )
    model = TECHNOLOGIES[label].rate
    rng = np.random.default_rng(rng)
    steps = max(1, math.ceil(duration_s / step_s - 1e-9))
    if steps > MAX_STEPS:
        raise TraceError(
            f"generate {label}: expected at most {MAX_STEPS:,} steps, got {steps:,} "
            f"({duration_s:g} s in steps of {step_s:g} s)"
        )
    phi = model.correlation_per_s**step_s
    innovation = model.sigma_log * math.sqrt(1.0 - phi**2)
    log_mean = math.log(model.mean_kbps)
    log_rate = np.empty(steps)
    log_rate[0] = log_mean + model.sigma_log * rng.standard_normal()
    noise = rng.standard_normal(steps)
    for i in range(1, steps):
        log_rate[i] = log_mean + phi * (log_rate[i - 1] - log_mean) + innovation * noise[i]
    rates = np.clip(np.exp(log_rate), model.min_kbps, model.max_kbps)
    fade_probability = model.fades_per_min / 60.0 * step_s
    i = 0
    while i < steps:
        if rng.random() < fade_probability:
            length = max(1, round(rng.uniform(model.fade_min_s, model.fade_max_s) / step_s))
            rates[i : i + length] = 0.0
            i += length  # at least one faded step, then one step of signal before the next fade
        i += 1
    times = np.arange(steps) * step_s
    return Trace(times, rates, (label,) * steps, float(duration_s), f"generated {label}")
