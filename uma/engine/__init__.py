"""The UMA engine's decisions as pure code: estimators, policies and the engine's parts (no SimPy)."""

from uma.engine.decisions import (
    DescriptionChunk,
    EngineEvent,
    EngineOutcome,
    FrameDecision,
    UnitSent,
)
from uma.engine.engine import UmaEngine
from uma.engine.estimator import EstimatorState, initial_estimate, update_estimate
from uma.engine.model import TRANSITIONS, ModelEvent, ModelState
from uma.engine.parts import DescriptionPlan
from uma.engine.policy import POLICIES, PolicyView, fixed_policy, oracle_policy, throughput_policy
from uma.engine.reports import KeyframeRequest, ReceiverReport

__all__ = [
    "UmaEngine",
    "FrameDecision",
    "EngineEvent",
    "EngineOutcome",
    "UnitSent",
    "DescriptionChunk",
    "DescriptionPlan",
    "ModelState",
    "ModelEvent",
    "TRANSITIONS",
    "EstimatorState",
    "initial_estimate",
    "update_estimate",
    "POLICIES",
    "PolicyView",
    "throughput_policy",
    "oracle_policy",
    "fixed_policy",
    "ReceiverReport",
    "KeyframeRequest",
]
