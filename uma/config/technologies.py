"""Technology labels: the names uma uses, and how the names found in trace files map onto them.

They live in `config` because scenario keys name technologies (`route[i].technology`,
`downlink.technologies`) and are checked when a scenario is loaded; `uma.traces` reads them here.

No units here. A label is one of `LABELS`, or "" when the technology is unknown. Files name the
same radio in many ways (`NetworkMode` of G-NetTrack logs: HSPA+, HSDPA, UMTS, ...); they all
become "3G", as the project's engine cares about the class of link, not the 3GPP release.
"""

from __future__ import annotations

__all__ = [
    "LABELS",
    "UNKNOWN_NAMES",
    "normalise_technology",
    "technology_label",
    "check_technologies",
]

LABELS: tuple[str, ...] = ("GSM", "GPRS", "EDGE", "3G", "LTE", "5G", "WLAN")

# Spellings that carry no technology (G-NetTrack writes "-" when the modem does not say).
UNKNOWN_NAMES = frozenset({"", "-", "UNKNOWN", "NONE", "N/A", "NA"})

_ALIASES = {
    "CSD": "GSM",
    "EGPRS": "EDGE",
    "UMTS": "3G",
    "WCDMA": "3G",
    "W-CDMA": "3G",
    "HSPA": "3G",
    "HSPA+": "3G",
    "HSPAP": "3G",
    "DC-HSPA+": "3G",
    "HSDPA": "3G",
    "HSUPA": "3G",
    "TD-SCDMA": "3G",
    "EVDO": "3G",
    "EV-DO": "3G",
    "4G": "LTE",
    "LTE+": "LTE",
    "LTE-A": "LTE",
    "LTE_CA": "LTE",
    "LTE-CA": "LTE",
    "NR": "5G",
    "NR5G": "5G",
    "5G-NSA": "5G",
    "5G-SA": "5G",
    "WIFI": "WLAN",
    "WI-FI": "WLAN",
    "802.11": "WLAN",
}


def technology_label(name: str) -> str | None:
    """The uma label for `name` ("" when it says nothing), or None when `name` is not a technology."""
    upper = name.strip().upper()
    if upper in UNKNOWN_NAMES:
        return ""
    if upper in LABELS:
        return upper
    return _ALIASES.get(upper)


def normalise_technology(name: str) -> str:
    """`name` as uma labels it (HSPA+/HSDPA/HSUPA/UMTS -> "3G", WiFi -> "WLAN", "-" -> "").

    A name that is no known technology comes back unchanged, so a caller can report it; use
    `technology_label` to tell the two cases apart.
    """
    label = technology_label(name)
    return name.strip() if label is None else label


def check_technologies(names) -> None:
    """Raise `ValueError` (a schema error once pydantic words it) unless every name of `names`
    is one of `LABELS`: the keys that name technologies take uma's labels, nothing else."""
    for name in names:
        if name not in LABELS:
            raise ValueError(f"expected technologies among {', '.join(LABELS)}, got {name!r}")
