"""MBC packets: several frames' parameter sets behind one small header, with a CRC32.

Units: bytes; frame indices count source frames.

Layout (big-endian header, then the range coder's 32-bit words little-endian, then the CRC):

| bytes | field |
|---|---|
| 0 | bit 7: every set is followed by its frame's block map changes (`uma.mbc.coding`, `uma.mbc.block_map`); bits 4-6: version (1); flags (bit 0: the first set is intra; bit 1: every set ends with the face's light, gain and offset; bit 2: the torso's motion, three values, comes before the light; bit 3: the camera's motion, two values, after the torso's) |
| 1-2 | sequence number (uint16, wraps) |
| 3-5 | first frame index (uint24, wraps after 7.7 days at 25 frames/s) |
| 6 | frame count (1-255): frames first .. first + count - 1, one set each |
| 7 | global quantiser step code (step = code / 16) |
| 8 .. n-5 | the coded sets (`uma.mbc.coding`), a multiple of 4 bytes |
| n-4 .. n-1 | CRC32 (zlib) of every byte before it |

12 bytes of our own per packet, on top of the 40 bytes of IP (20), UDP (8) and RTP (12)
headers. RTP has its own sequence number and timestamp; ours are kept so that the codec is
whole without RTP (a file, a test), at 6 bytes a packet.
"""

from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass

import numpy as np

from uma.mbc.errors import PacketError

__all__ = [
    "Packet",
    "parse_packet",
    "VERSION",
    "HEADER_BYTES",
    "CRC_BYTES",
    "IP_UDP_RTP_BYTES",
    "SEQ_MODULUS",
]

VERSION = 1
HEADER_BYTES = 8
CRC_BYTES = 4
IP_UDP_RTP_BYTES = 40
SEQ_MODULUS = 1 << 16
FRAME_MODULUS = 1 << 24
_HEADER = struct.Struct(">BH3sBB")


@dataclass(frozen=True, eq=False)
class Packet:
    """One packet: `count` frames from `first_frame`, the first set intra if `intra`."""

    seq: int
    first_frame: int
    count: int
    intra: bool
    global_code: int
    words: np.ndarray  # uint32
    light: bool = False  # the sets carry light (`uma.mbc.units.LIGHT_NAMES`)
    body: bool = False  # the sets carry the torso's motion (`uma.mbc.units.BODY_KINDS`)
    camera: bool = False  # and the camera's (`uma.mbc.units.CAMERA_KINDS`)
    block_map: bool = False  # each set is followed by its frame's block map changes

    def __post_init__(self) -> None:
        if not 0 <= self.seq < SEQ_MODULUS or not 1 <= self.count <= 255:
            raise ValueError(f"packet: seq 0-65535 and count 1-255 expected, got {self}")
        if not 1 <= self.global_code <= 255:
            raise ValueError(f"packet: global step code 1-255 expected, got {self.global_code}")
        if self.camera and not self.body:
            raise ValueError("packet: a camera motion comes only with the body motion")

    def to_bytes(self) -> bytes:
        first = (self.first_frame % FRAME_MODULUS).to_bytes(3, "big")
        head = _HEADER.pack(
            (VERSION << 4)
            | int(self.intra)
            | (int(self.light) << 1)
            | (int(self.body) << 2)
            | (int(self.camera) << 3)
            | (int(self.block_map) << 7),
            self.seq,
            first,
            self.count,
            self.global_code,
        )
        body = head + np.asarray(self.words, dtype="<u4").tobytes()
        return body + struct.pack(">I", zlib.crc32(body))

    @property
    def size_bytes(self) -> int:
        return HEADER_BYTES + 4 * len(self.words) + CRC_BYTES

    @property
    def wire_bytes(self) -> int:
        """Size with the IP, UDP and RTP headers."""
        return self.size_bytes + IP_UDP_RTP_BYTES


def parse_packet(data: bytes, *, where: str = "packet") -> Packet:
    """A packet from its bytes; truncated, corrupted or foreign data raises `PacketError`
    naming `where`."""
    if not isinstance(data, bytes | bytearray | memoryview):
        raise PacketError(f"{where}: expected bytes, got {type(data).__name__}")
    data = bytes(data)
    n = len(data)
    if n < HEADER_BYTES + CRC_BYTES:
        raise PacketError(
            f"{where}: truncated: {n} bytes, a packet has at least {HEADER_BYTES + CRC_BYTES}"
        )
    (crc,) = struct.unpack(">I", data[-CRC_BYTES:])
    if zlib.crc32(data[:-CRC_BYTES]) != crc:
        raise PacketError(f"{where}: checksum mismatch ({n} bytes): corrupted or truncated")
    if (n - HEADER_BYTES - CRC_BYTES) % 4:
        raise PacketError(f"{where}: payload of {n - 12} bytes is not whole 32-bit words")
    flags, seq, first, count, code = _HEADER.unpack(data[:HEADER_BYTES])
    if (flags >> 4) & 0x07 != VERSION or (flags & 0x08 and not flags & 0x04):
        raise PacketError(
            f"{where}: version/flags byte {flags:#04x}, expected version {VERSION} (and a "
            f"camera motion only with the body motion)"
        )
    if count == 0 or code == 0:
        raise PacketError(f"{where}: frame count and global step must be >= 1, got {count}, {code}")
    words = np.frombuffer(data[HEADER_BYTES:-CRC_BYTES], dtype="<u4").astype(np.uint32)
    return Packet(
        seq=seq,
        first_frame=int.from_bytes(first, "big"),
        count=count,
        intra=bool(flags & 1),
        global_code=code,
        words=words,
        light=bool(flags & 2),
        body=bool(flags & 4),
        camera=bool(flags & 8),
        block_map=bool(flags & 0x80),
    )
