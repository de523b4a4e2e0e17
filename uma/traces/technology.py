"""Radio access technologies: their names, link defaults, and a rate model to generate traces.

Units: rates in kbit/s, delays in ms (one way, engine to handset, core network included),
loss as a fraction of packets, times in seconds.

Typical figures (downlink, a moving user, late 2000s to today): GSM circuit-switched data 9.6
kbit/s with ~200 ms one way; GPRS (CS-2, 3-4 slots) 20-50 kbit/s, RTT 400-1000 ms (we take the
better end, 200 ms one way: early networks were slower still); EDGE 100-200 kbit/s, RTT
~300 ms; 3G (UMTS/HSDPA) a few hundred kbit/s to 2 Mbit/s, RTT 100-200 ms; LTE tens of Mbit/s,
RTT ~50 ms; WLAN (802.11g/n at range) a few Mbit/s to 20, a few ms. These set
defaults only: a scenario overrides delay and loss per technology, and real traces give rates.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.errors import TraceError

__all__ = ["Technology", "TECHNOLOGIES", "technology_defaults", "normalise_technology", "generate"]


@dataclass(frozen=True)
class Technology:
    """Link defaults and a log-normal AR(1) rate model, clipped to [min_kbps, max_kbps]."""

    name: str
    delay_ms: float
    loss_rate: float
    mean_kbps: float
    min_kbps: float
    max_kbps: float
    sigma_log: float  # standard deviation of log-rate
    correlation: float  # AR(1) coefficient per second
    fades_per_min: float = 0.0  # short drops to zero (1-3 s): cell edges, tunnels


TECHNOLOGIES: dict[str, Technology] = {
    t.name: t
    for t in (
        Technology("GSM", 200.0, 0.005, 9.6, 4.8, 9.6, 0.15, 0.9, fades_per_min=0.5),
        Technology("GPRS", 200.0, 0.01, 35.0, 8.0, 53.6, 0.35, 0.85, fades_per_min=1.0),
        Technology("EDGE", 150.0, 0.01, 150.0, 40.0, 236.0, 0.35, 0.85, fades_per_min=0.5),
        Technology("3G", 60.0, 0.005, 800.0, 150.0, 2000.0, 0.5, 0.8, fades_per_min=0.2),
        Technology("LTE", 25.0, 0.002, 15000.0, 1000.0, 50000.0, 0.6, 0.8),
        Technology("5G", 15.0, 0.001, 80000.0, 5000.0, 300000.0, 0.6, 0.8),
        Technology("WLAN", 5.0, 0.002, 8000.0, 1500.0, 20000.0, 0.4, 0.8),
    )
}

_UNKNOWN = Technology("", 50.0, 0.0, 1000.0, 1.0, 1e6, 0.0, 0.0)

_ALIASES = {
    "HSPA+": "3G",
    "HSPA": "3G",
    "HSDPA": "3G",
    "HSUPA": "3G",
    "UMTS": "3G",
    "WCDMA": "3G",
    "EVDO": "3G",
    "WIFI": "WLAN",
    "WI-FI": "WLAN",
    "NR": "5G",
}


def normalise_technology(label: str) -> str:
    """A technology label as uma names it: HSPA+/HSDPA/HSUPA/UMTS -> 3G, WiFi -> WLAN, ..."""
    text = label.strip()
    if not text or text == "-":
        return ""
    upper = text.upper()
    if upper in TECHNOLOGIES:
        return upper
    return _ALIASES.get(upper, text)


def technology_defaults(name: str) -> Technology:
    """The defaults of `name`; unknown or empty labels get a neutral 50 ms, lossless link."""
    return TECHNOLOGIES.get(normalise_technology(name), _UNKNOWN)


def generate(technology: str, duration_s: float, *, rng, step_s: float = 1.0):
    """A synthetic trace of `technology` from its rate model, reproducible from `rng`."""
    from uma.traces.trace import Trace

    tech = TECHNOLOGIES.get(normalise_technology(technology))
    if tech is None:
        raise TraceError(
            f"cannot generate rates for technology {technology!r}; expected one of "
            f"{', '.join(TECHNOLOGIES)}"
        )
    if not duration_s > 0 or not step_s > 0:
        raise TraceError(
            f"generate {technology}: expected positive durations, got {duration_s}, {step_s}"
        )
    rng = np.random.default_rng(rng)
    steps = max(1, int(np.ceil(duration_s / step_s)))
    phi = tech.correlation**step_s
    innovation = tech.sigma_log * np.sqrt(1.0 - phi**2)
    log_mean = np.log(tech.mean_kbps)
    log_rate = np.empty(steps)
    log_rate[0] = log_mean + tech.sigma_log * rng.standard_normal()
    noise = rng.standard_normal(steps)
    for i in range(1, steps):
        log_rate[i] = log_mean + phi * (log_rate[i - 1] - log_mean) + innovation * noise[i]
    rates = np.clip(np.exp(log_rate), tech.min_kbps, tech.max_kbps)
    fade_prob = tech.fades_per_min / 60.0 * step_s
    i = 0
    while i < steps:
        if rng.random() < fade_prob:
            length = max(1, int(round(rng.uniform(1.0, 3.0) / step_s)))
            rates[i : i + length] = 0.0
            i += length
        i += 1
    times = np.arange(steps) * step_s
    return Trace(times, rates, (tech.name,) * steps, float(duration_s), f"generated {tech.name}")
