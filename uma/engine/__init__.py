"""The UMA engine's decisions as pure code: estimator, rate policies, state machine (no SimPy)."""

from uma.engine.engine import EngineEvent, FrameDecision, UmaEngine
from uma.engine.estimator import EstimatorState, initial_estimate, update_estimate
from uma.engine.policy import POLICIES, PolicyView, fixed_policy, oracle_policy, throughput_policy
from uma.engine.reports import KeyframeRequest, ReceiverReport

__all__ = [
    "UmaEngine",
    "FrameDecision",
    "EngineEvent",
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
