"""Scenario configuration: YAML parsed once into frozen, validated objects.

Errors carry the file, line and key path of the bad value.
"""

from uma.config.load import default_scenario_path, load_scenario, scenario_from_dict
from uma.config.scenario import (
    DownlinkConfig,
    EngineConfig,
    EstimatorConfig,
    FeedbackConfig,
    MetricsConfig,
    ReceiverConfig,
    Scenario,
    SegmentConfig,
    SenderConfig,
    SourceConfig,
    TechnologyOverride,
    UplinkConfig,
)
from uma.config.yamlfile import KeyLines, load_yaml

__all__ = [
    "Scenario",
    "SourceConfig",
    "SenderConfig",
    "UplinkConfig",
    "DownlinkConfig",
    "TechnologyOverride",
    "SegmentConfig",
    "FeedbackConfig",
    "EstimatorConfig",
    "EngineConfig",
    "ReceiverConfig",
    "MetricsConfig",
    "KeyLines",
    "load_yaml",
    "load_scenario",
    "scenario_from_dict",
    "default_scenario_path",
]
