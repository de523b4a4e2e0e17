"""Project errors.

Every error a user can cause subclasses both `UmaError` and a builtin, so callers may catch
either (as PyAV does). The CLI turns an `UmaError` into one line on stderr and `exit_code`.
Messages name where the bad value came from (file and line, or key path) and what was expected.
"""

from __future__ import annotations

__all__ = [
    "UmaError",
    "ConfigError",
    "TraceError",
    "VideoError",
    "FaceError",
    "RunError",
    "OutputError",
]


class UmaError(Exception):
    """Base of every error `uma` raises on purpose; `exit_code` is the CLI's exit status."""

    exit_code = 2


class ConfigError(UmaError, ValueError):
    """A scenario or experiment file is malformed: unknown key, wrong type or unit, missing file."""


class TraceError(UmaError, ValueError):
    """A bandwidth trace cannot be read: malformed line, negative or NaN value, no samples."""


class VideoError(UmaError, ValueError):
    """A video source or bitstream cannot be opened or decoded."""


class FaceError(UmaError, ValueError):
    """A face model, feature-point file or face image is unusable."""


class RunError(UmaError, RuntimeError):
    """The run itself found a problem (a failed check); exit status 1."""

    exit_code = 1


class OutputError(UmaError, OSError):
    """Results cannot be written where asked: a file in the way, no permission, disk full."""
