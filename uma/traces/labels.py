"""Technology labels, as `uma.config.technologies` defines them (kept here for trace readers)."""

from uma.config.technologies import LABELS, UNKNOWN_NAMES, normalise_technology, technology_label

__all__ = ["LABELS", "UNKNOWN_NAMES", "normalise_technology", "technology_label"]
