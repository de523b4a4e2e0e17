"""The model-based codec's error: a packet that cannot be decoded.

Subclasses `UmaError` and `ValueError` (see `uma.errors`), so a receiver may catch either.
"""

from __future__ import annotations

from uma.errors import UmaError

__all__ = ["PacketError"]


class PacketError(UmaError, ValueError):
    """A packet is truncated, corrupted (checksum), of another version, or decodes to
    parameters outside their range; the message names the packet."""
