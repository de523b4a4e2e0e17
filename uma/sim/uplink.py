"""The sender's uplink stream, computed once: content-addressed, reused across runs.

Units: pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8; sizes in bits and bytes.

The sender's stream and the engine's decode of it are the same in every run of a given source
and sender setting, whatever the engine, the downlink or the seed's other streams do. An
`UplinkMemo` keeps them: each frame is addressed by a hash chained over the sender's settings
(the uplink codec, `sender.rate_kbps`, `preset`, `keyint_frames`, the picture size and rate),
the library versions (PyAV and the FFmpeg libraries it carries, NumPy) and every source frame's
bytes so far, so a frame is found only when the whole stream up to it is the same. A run that
finds frames takes the coded frame and the decoded picture instead of coding and decoding;
when it meets a frame the memo lacks after frames it found (a longer run, or other content),
the coders catch up on the frames they skipped (kept while found) and go on live, so a result
is byte for byte what computing afresh gives (`tests/sim/test_uplink_memo.py`). The memo lives
in one process (`uma bench sim` shares one between the run and its replay); it holds a picture
per frame, so it is opt-in (`run_scenario(..., uplink=memo)`).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field, replace

import numpy as np

__all__ = [
    "UplinkFrame",
    "UplinkMemo",
    "UplinkSender",
    "UplinkReceiver",
    "settings_key",
    "chain",
]


@dataclass(frozen=True)
class UplinkFrame:
    """One frame of the uplink stream as the sender coded it; `key` addresses it in a memo;
    `taken`: the sender took it from the memo (the engine takes its picture from there too);
    `catch_up`: what the engine's decoder must decode first (the frames the run took from
    the memo before this one, which it did not code)."""

    data: bytes
    pts: int
    is_keyframe: bool
    key: bytes = b""
    taken: bool = False
    catch_up: tuple[bytes, ...] = ()

    @property
    def size_bits(self) -> int:
        return 8 * len(self.data)


def settings_key(codec: str, sender, *, width: int, height: int, fps: float) -> bytes:
    """The start of the chain: the uplink codec and sender settings, the libraries' versions."""
    import av

    text = repr(
        (codec, float(sender.rate_kbps), sender.preset, int(sender.keyint_frames), width, height,
         float(fps), av.__version__, sorted(av.library_versions.items()), np.__version__)
    )  # fmt: skip
    return hashlib.blake2b(text.encode(), digest_size=20).digest()


def chain(key: bytes, frame: np.ndarray) -> bytes:
    """The address of `frame` after the frames whose address is `key`: the first 20 bytes of
    a SHA-256 (a content address, never an output; docs/mbc.md, session mbc12)."""
    digest = hashlib.sha256(key)
    digest.update(repr((frame.shape, str(frame.dtype))).encode())
    digest.update(np.ascontiguousarray(frame).data)
    return digest.digest()[:20]


@dataclass
class UplinkMemo:
    """Coded frames and decoded pictures by address; `hits` and `misses` count lookups."""

    frames: dict[bytes, UplinkFrame] = field(default_factory=dict)
    pictures: dict[bytes, np.ndarray | None] = field(default_factory=dict)
    hits: int = 0
    misses: int = 0

    def found(self, key: bytes) -> UplinkFrame | None:
        frame = self.frames.get(key)
        if frame is None or key not in self.pictures:
            self.misses += 1
            return None
        self.hits += 1
        return frame

    def keep(self, frame: UplinkFrame) -> None:
        self.frames[frame.key] = frame

    def keep_picture(self, key: bytes, picture: np.ndarray | None) -> None:
        self.pictures[key] = picture


class UplinkSender:
    """The sender's side through a memo: a frame found is taken, one not found is coded live
    (after catching the encoder up on the frames taken before it), and so is every later one."""

    def __init__(self, encoder, memo: UplinkMemo, start: bytes) -> None:
        self.encoder, self.memo, self.key = encoder, memo, start
        self.skipped: list[np.ndarray] | None = []  # frames taken, not coded (None: live)

    def encode(self, frame: np.ndarray) -> UplinkFrame:
        self.key = chain(self.key, frame)
        found = self.memo.found(self.key) if self.skipped is not None else None
        if found is not None:
            self.skipped.append(frame)
            return replace(found, taken=True)
        catch_up = tuple(self.encoder.encode(old).data for old in self.skipped or ())
        self.skipped = None  # live from here on: the memo is not asked again
        out = self.encoder.encode(frame)
        coded = UplinkFrame(out.data, out.pts, bool(out.is_keyframe), self.key)
        self.memo.keep(coded)
        return replace(coded, catch_up=catch_up) if catch_up else coded


class UplinkReceiver:
    """The engine's decoder of the uplink through a memo: a frame the sender took from the
    memo gives its kept picture; one coded live is decoded (its catch-up first) and kept."""

    def __init__(self, decoder, memo: UplinkMemo) -> None:
        self.decoder, self.memo = decoder, memo

    def decode(self, encoded: UplinkFrame) -> np.ndarray | None:
        if encoded.taken:
            return self.memo.pictures[encoded.key]
        for data in encoded.catch_up:
            self.decoder.decode(data)
        picture = self.decoder.decode(encoded.data)
        self.memo.keep_picture(encoded.key, picture)
        return picture
