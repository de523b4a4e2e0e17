"""Scenario configuration: YAML parsed once into frozen, validated objects.

Errors carry the file, line and key path of the bad value. The whole scenario and the loaders
are here; each section's models live in their own module (`uma.config.network`, `.engine`,
`.codecs`, `.receiver`, `.faults`; `uma.config.scenario` re-exports them all).
"""

from uma.config.engine import EngineConfig, EstimatorConfig
from uma.config.load import default_scenario_path, load_scenario, scenario_from_dict
from uma.config.network import DownlinkConfig, FeedbackConfig, SegmentConfig
from uma.config.receiver import MetricsConfig, ReceiverConfig
from uma.config.scenario import Scenario, SourceConfig
from uma.config.yamlfile import KeyLines, load_yaml

__all__ = [
    "Scenario",
    "load_scenario",
    "scenario_from_dict",
    "default_scenario_path",
    "KeyLines",
    "load_yaml",
    # the sections callers most often build or adjust; every other one is in its module
    "SourceConfig",
    "SegmentConfig",
    "DownlinkConfig",
    "FeedbackConfig",
    "EngineConfig",
    "EstimatorConfig",
    "ReceiverConfig",
    "MetricsConfig",
]
