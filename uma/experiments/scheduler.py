"""Check, before Dask is asked to connect, that a Dask scheduler answers at an address.

`distributed.Client` given something that is not a scheduler can hang past its timeout, read
a garbage length prefix as a request for exabytes, or stall in `Client.__del__` after a bad
address. So the address is parsed first (`tcp://HOST:PORT`), then one socket connects within
the timeout and reads the greeting a Dask server sends unasked on every connection (its
handshake: a length-prefixed msgpack mapping), bounded in size. Only then does the caller
build a `Client`. Each failure is one `ConfigError` line naming the address.
"""

from __future__ import annotations

import socket
import struct
import time
from urllib.parse import urlsplit

from uma.errors import ConfigError

__all__ = ["parse_scheduler_address", "check_scheduler", "GREETING_MAX_BYTES"]

GREETING_MAX_BYTES = 65_536  # a Dask handshake is a few hundred bytes
_LENGTH = struct.Struct("Q")  # the prefix Dask's TCP comm writes (distributed/comm/tcp.py)


def parse_scheduler_address(address: str) -> tuple[str, int]:
    """`tcp://HOST:PORT` -> (host, port); `ConfigError` for anything else."""
    expected = f"--scheduler: expected tcp://HOST:PORT, got {address!r}"
    parts = urlsplit(address)
    try:
        port = parts.port
    except ValueError:
        raise ConfigError(expected) from None
    if parts.scheme != "tcp" or not parts.hostname or port is None or port == 0:
        raise ConfigError(expected)
    if parts.path not in ("", "/") or parts.query or parts.fragment or parts.username:
        raise ConfigError(expected)
    return parts.hostname, port


def _read_exactly(sock: socket.socket, count: int, deadline: float, address: str) -> bytes:
    data = bytearray()
    while len(data) < count:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            raise TimeoutError
        sock.settimeout(remaining)
        chunk = sock.recv(count - len(data))
        if not chunk:
            raise ConfigError(
                f"--scheduler: {address!r} closed the connection without a Dask greeting "
                f"(not a Dask scheduler?)"
            )
        data += chunk
    return bytes(data)


def _greeting_ok(body: bytes) -> bool:
    try:
        from distributed.protocol.core import loads
        from distributed.protocol.utils import unpack_frames

        frames, missing = unpack_frames(body, partial=True)
        message = loads(frames, deserialize=False) if not missing else None
    except Exception:  # any garbage: not Dask's protocol
        return False
    return isinstance(message, dict) and ("pickle-protocol" in message or "compression" in message)


def check_scheduler(address: str, *, timeout_s: float) -> None:
    """Return when a Dask server greets at `address` within `timeout_s`, else `ConfigError`."""
    host, port = parse_scheduler_address(address)
    if not timeout_s > 0:
        raise ConfigError(f"--timeout: expected a positive number of seconds, got {timeout_s}")
    deadline = time.monotonic() + timeout_s
    not_dask = f"--scheduler: {address!r} does not speak Dask's protocol (not a Dask scheduler?)"
    try:
        with socket.create_connection((host, port), timeout=timeout_s) as sock:
            head = _read_exactly(sock, _LENGTH.size, deadline, address)
            (length,) = _LENGTH.unpack(head)
            if not 8 <= length <= GREETING_MAX_BYTES:
                raise ConfigError(not_dask)
            body = _read_exactly(sock, length, deadline, address)
    except TimeoutError:
        raise ConfigError(
            f"--scheduler: no Dask scheduler answered at {address!r} within {timeout_s:g} s "
            f"(--timeout)"
        ) from None
    except OSError as err:
        reason = err.strerror or str(err) or type(err).__name__
        raise ConfigError(
            f"--scheduler: cannot reach a Dask scheduler at {address!r} ({reason})"
        ) from None
    if not _greeting_ok(body):
        raise ConfigError(not_dask)
