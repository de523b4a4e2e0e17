"""Rate control, pure: delivery reports, uma's controller, the GCC baseline, the skip rule.

No clock, no codec, no SimPy: events in (a packet's arrival, a feedback report, a handover),
decisions out (`RateDecision`: a target rate and sometimes a `ProbeRequest`).
"""

from uma.control.actions import ProbeRequest, RateDecision
from uma.control.controller import UmaController
from uma.control.delivery import DeliveryReport, DeliverySettings, DeliveryTracker, PacketRecord
from uma.control.gcc import GccController
from uma.control.settings import UmaSettings
from uma.control.skip import should_skip

__all__ = [
    "DeliveryReport",
    "DeliverySettings",
    "DeliveryTracker",
    "GccController",
    "PacketRecord",
    "ProbeRequest",
    "RateDecision",
    "UmaController",
    "UmaSettings",
    "should_skip",
]
