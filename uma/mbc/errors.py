"""The model-based codec's errors: a packet that cannot be decoded, a scene it cannot draw.

Subclasses `UmaError` and `ValueError` (see `uma.errors`), so a receiver may catch either.
"""

from __future__ import annotations

from uma.errors import UmaError

__all__ = ["PacketError", "SceneError"]


class PacketError(UmaError, ValueError):
    """A packet is truncated, corrupted (checksum), of another version, or decodes to
    parameters outside their range; the message names the packet."""


class SceneError(UmaError, ValueError):
    """A reference picture or pose the renderer cannot draw from (wrong size, no face), or
    illumination outside its range; the message names the value and where it came from."""
