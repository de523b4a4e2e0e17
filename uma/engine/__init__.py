"""The UMA engine's decisions as pure code: estimators, policies and the engine's parts (no SimPy)."""

from uma.engine.decisions import (
    AdoptRefresh,
    CodedReport,
    DiscardRefresh,
    EngineEvent,
    EngineOutcome,
    FrameDecision,
    Initialise,
    OutgoingUnit,
    PaceDecision,
    RefreshCoded,
    SendPacket,
    Tally,
    WakePacer,
)
from uma.engine.engine import UmaEngine
from uma.engine.estimator import EstimatorState
from uma.engine.model import TRANSITIONS, ModelEvent, ModelState
from uma.engine.pacer import PacedPacket, Pacer, PacerRelease
from uma.engine.parts import DescriptionPlan
from uma.engine.policy import POLICIES, PolicyView, fixed_policy, oracle_policy, throughput_policy
from uma.engine.rate import RATE_CONTROLS, RateControl, make_rate
from uma.engine.refresh import (
    REFRESH_TRANSITIONS,
    RefreshEvent,
    RefreshOrder,
    RefreshPlanner,
    RefreshState,
)
from uma.engine.reports import KeyframeRequest, ReceiverReport

__all__ = [
    "UmaEngine",
    "FrameDecision",
    "EngineEvent",
    "EngineOutcome",
    "SendPacket",
    "Initialise",
    "AdoptRefresh",
    "DiscardRefresh",
    "WakePacer",
    "Tally",
    "CodedReport",
    "OutgoingUnit",
    "RefreshCoded",
    "PaceDecision",
    "Pacer",
    "PacedPacket",
    "PacerRelease",
    "DescriptionPlan",
    "ModelState",
    "ModelEvent",
    "TRANSITIONS",
    "EstimatorState",
    "RateControl",
    "RATE_CONTROLS",
    "make_rate",
    "POLICIES",
    "PolicyView",
    "throughput_policy",
    "oracle_policy",
    "fixed_policy",
    "ReceiverReport",
    "KeyframeRequest",
    "RefreshPlanner",
    "RefreshOrder",
    "RefreshState",
    "RefreshEvent",
    "REFRESH_TRANSITIONS",
]
