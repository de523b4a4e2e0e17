"""A block map beside the face's parameters: where the receiver shows, instead of its rendering,
a picture it already holds (its rendering softened or blurred, the plate, the reference).

Units: pixels; bits; kbit/s; pictures planar YUV 4:2:0 (H * 3 // 2, W) uint8.

The receiver keeps one choice per block of `BLOCK_PX` pixels (`CHOICES`; all "rendering" at
first). The engine, which has the source and mirrors the receiver's picture, sends a few
changes a frame: the blocks where another choice errs least against the source by the most
squared luma error, greedily, as many as its bit allowance pays for. Only the blocks of a
window of `WINDOW_BLOCKS` a side about the drawn face can change (their index is coded within
it); a block that leaves the window goes back to the rendering at both ends. The allowance is a
bucket filled at `MAP_TOTAL_KBPS` less the parameter stream's own bits, so stream and map
together stay under it. Each frame costs an Exp-Golomb count of its changes and, per change,
the block's index in the window and which of the other choices (`change_bits`). Both ends draw
the same picture from the same decoded parameters, so the engine's choice is exact at the
receiver. Guards against seams, known to both ends from the drawn face: a choice ends once the
face has moved `STALE_PX` from where it was taken; the plate and the reference are drawn only at
a block's pixels outside the drawn face, the face's own pixels keep the rendering (and the
plate is never chosen where it has not seen them); the face's interior never blurred; a block's
edge fades into its neighbours. Measured in docs/mbc.md (sessions mbc7, mbc8).
"""

from __future__ import annotations

import math

import numpy as np

from uma.mbc.block_window import BLOCK_PX, WINDOW_BLOCKS
from uma.mbc.block_window import margin_box as _margin_box
from uma.mbc.block_window import window_about as _window_about
from uma.mbc.block_window import window_crop as _window_crop
from uma.mbc.errors import SceneError

__all__ = [
    "BlockMap",
    "BLOCK_PX",
    "WINDOW_BLOCKS",
    "CHOICES",
    "MAP_TOTAL_KBPS",
    "change_bits",
    "count_bits",
]

# A chosen block's edge fades into its neighbours over this (Gaussian sigma; 0 hard): hard
# 8x8 steps showed along akiyo's hair. Frames 150-299, face box dB akiyo | carphone: 0 23.207
# | 21.424, 1.5 23.258 | 21.495, 3 23.263 | 21.533 (docs/mbc.md, session mbc7).
FEATHER_SIGMA_PX = 3.0
# A block's choice ends when the face has moved this far from where it was when the block took
# it (both ends see the drawn face): a plate or reference block left behind by a moving head
# would show a piece of the old scene beside the new one.
STALE_PX = 8.0
CHOICES = ("rendering", "softened", "blurred", "plate", "reference")
BLUR_SIGMAS_PX = (1.0, 2.0)  # "softened", "blurred": the rendering's Gaussian blur
MAP_TOTAL_KBPS = 2.4  # the parameter stream and the map together (the target is 2.5)
# At most this much allowance saved for a later frame, or owed after the stream's own peaks
# (an intra set); the map pays its count's bit every frame even when it owes.
BUCKET_MAX_BITS = 200.0


def count_bits(count: int) -> int:
    """Bits of the Exp-Golomb code of a frame's change count `count` (0: one bit)."""
    return 2 * int(math.floor(math.log2(count + 1))) + 1


def change_bits(window_blocks: int) -> int:
    """Bits of one change: the block's index among `window_blocks` and the new choice among
    the other `len(CHOICES) - 1`."""
    return math.ceil(math.log2(max(window_blocks, 2))) + math.ceil(math.log2(len(CHOICES) - 1))


class BlockMap:
    """Both ends' block map over pictures of `size` (W, H) at `fps`: `step` chooses a frame's
    changes (the engine's side, against the source), takes them (the receiver's side) and
    returns the picture shown; `bits` counts every bit sent."""

    def __init__(self, size: tuple[int, int], fps: float, total_kbps: float = MAP_TOTAL_KBPS):
        width, height = size
        if width < BLOCK_PX or height < BLOCK_PX or not fps > 0:
            raise SceneError(
                f"block map: expected a picture of at least {BLOCK_PX} px a side at a positive "
                f"frame rate, got size {size} at {fps} frames/s"
            )
        self.grid = (height // BLOCK_PX, width // BLOCK_PX)
        # The window's blocks: a change's index is coded among these (`uma.mbc.coding`).
        self.map_blocks = min(WINDOW_BLOCKS, self.grid[0]) * min(WINDOW_BLOCKS, self.grid[1])
        self.sent = np.zeros((0, 2), np.int64)  # the last frame's changes: block index, code
        self.state = np.zeros(self.grid, np.int8)
        # Where the face's centre was when each block took its choice (x, y px).
        self.anchor = np.zeros((2, *self.grid), np.float32)
        self._centre = (0.0, 0.0)
        self.frame_bits = total_kbps * 1000.0 / fps
        self.bucket = 0.0
        self.bits = 0
        self.changes = 0
        self._weights: dict = {}  # by choice: its blocks and their faded weights (`_weights`)

    def window(self, face: np.ndarray) -> tuple[int, int, int, int] | None:
        """The window (b0, a0, b1, a1) in blocks (columns b, rows a) about the drawn `face`
        (H, W bool); None without a face."""
        found = _window_about(face, self.grid)
        if found is not None:
            self._centre = found[1]
        return None if found is None else found[0]

    def read_box(self, face: np.ndarray) -> tuple[int, int, int, int] | None:
        """The box (x0, y0, x1, y1) of the picture the engine's choice reads on a frame whose
        drawn face is `face`: the window and its blurs' margin; None without a face."""
        found = _window_about(face, self.grid)
        if found is None:
            return None
        y0, x0, y1, x1 = _margin_box(found[0], face.shape[::-1])[1]
        return x0, y0, x1, y1

    def step(self, shown, face, plate, reference, source=None, stream_bits=0.0, plate_known=None,
             changes=None, *, compose=True):  # fmt: skip
        """The picture shown for a frame whose rendering is `shown` with the face at `face`;
        `plate`, `reference` the receiver's (`plate_known`: the pixels the plate has seen;
        None: all); with `source` (the engine's frame) the frame's changes are chosen within
        the allowance left by `stream_bits` and kept in `sent` (block index in the window,
        choice code: which of the block's other choices); a receiver passes the decoded
        `changes` instead (a change the map cannot take: `SceneError`). Without `compose`
        (the engine's side, which shows nothing) the state moves the same but nothing is
        drawn (None; `shown`'s chroma is then never read). Only the choices a block holds are
        drawn (the engine's choice draws every choice's luma)."""
        window = self.window(face)
        self.bucket = float(np.clip(self.bucket + self.frame_bits - stream_bits,
                                    -BUCKET_MAX_BITS, BUCKET_MAX_BITS))  # fmt: skip
        self.sent = np.zeros((0, 2), np.int64)
        if window is None:
            self.state[:] = 0
            if changes is not None and len(changes):
                raise SceneError(f"block map: {len(changes)} changes for a frame without a face")
            return shown
        if source is None and (changes is None or not len(changes)) and not self.state.any():
            # Holding nothing, taking nothing: nothing to end or draw; the empty count is paid.
            if changes is not None:
                self.bits += count_bits(0)
            return shown if compose else None
        c0, r0, c1, r1 = window
        outside = np.ones(self.grid, bool)
        outside[r0:r1, c0:c1] = False
        self.state[outside] = 0
        moved = np.hypot(self.anchor[0] - self._centre[0], self.anchor[1] - self._centre[1])
        self.state[moved > STALE_PX] = 0
        # A choice the block may no longer take (the face has reached into it) ends at both ends.
        barred = _barred(face, plate_known, window)
        state = self.state[r0:r1, c0:c1]
        state[np.take_along_axis(barred, state[None].astype(np.intp), 0)[0]] = 0
        on_face = _window_crop(face, window)
        lumas = [None] * len(CHOICES)
        if source is not None:
            lumas = _candidates(shown, plate, reference, window, on_face)
            self._choose(lumas, source, window, barred)
        elif changes is not None:
            self._take(np.asarray(changes, np.int64).reshape(-1, 2), window, barred)
        if not compose:
            return None
        state = self.state[r0:r1, c0:c1]
        return _compose(shown, lumas, state, window, (plate, reference), on_face, self._weights)

    def broke(self, stream_bits: float = 0.0) -> bool:
        """Whether this frame's allowance, once filled, cannot pay for one change (the engine
        then chooses nothing: `hold`)."""
        bucket = float(np.clip(self.bucket + self.frame_bits - stream_bits,
                               -BUCKET_MAX_BITS, BUCKET_MAX_BITS))  # fmt: skip
        return bucket < count_bits(1) + change_bits(self.map_blocks)

    def hold_with(self, renderer, face: np.ndarray, stream_bits: float = 0.0) -> None:
        """`hold` with the plate of `renderer` (as `step_with`)."""
        self.hold(face, stream_bits, None if renderer.plate is None else renderer.plate.known)

    def hold(self, face: np.ndarray, stream_bits: float = 0.0, plate_known=None) -> None:
        """The engine's frame when `broke`: the state moves as `step` with the source moves it
        when nothing is affordable (blocks leaving the window, gone stale or barred go back to
        the rendering; the empty count is paid), from the drawn `face` alone: no picture is
        drawn or compared."""
        none = np.zeros((0, 2), np.int64)
        self.step(None, face, None, None, None, stream_bits, plate_known, none, compose=False)
        if face.any():  # `step` paid the count as a receiver does; the engine's bucket too
            self.bucket -= count_bits(0)

    def idle(self, stream_bits: float = 0.0) -> bool:
        """The engine's shortcut: True when the map holds no choice and its allowance after
        this frame cannot pay for one change: the frame's (empty) change count is counted and
        nothing need be drawn or chosen (the receiver's `step` with no changes keeps the same
        state); False, changing nothing, otherwise."""
        bucket = float(np.clip(self.bucket + self.frame_bits - stream_bits,
                               -BUCKET_MAX_BITS, BUCKET_MAX_BITS))  # fmt: skip
        if self.state.any() or bucket >= count_bits(1) + change_bits(self.map_blocks):
            return False
        self.bucket = bucket - count_bits(0)
        self.bits += count_bits(0)
        self.sent = np.zeros((0, 2), np.int64)
        return True

    def step_with(self, renderer, shown, face, source=None, stream_bits=0.0, changes=None, *,
                  compose=True):  # fmt: skip
        """`step` with the plate and the reference of `renderer` (a `uma.mbc.SceneRenderer`;
        without a plate, the reference serves as one)."""
        plate = renderer.plate_picture()
        known = None if renderer.plate is None or plate is None else renderer.plate.known
        plate = renderer.reference if plate is None else plate
        return self.step(shown, face, plate, renderer.reference, source, stream_bits, known,
                         changes, compose=compose)  # fmt: skip

    def _choose(self, lumas, source: np.ndarray, window, barred: np.ndarray) -> None:
        """The engine's changes for this frame, taken; their bits counted."""
        c0, r0, c1, r1 = window
        y0, x0, y1, x1 = r0 * BLOCK_PX, c0 * BLOCK_PX, r1 * BLOCK_PX, c1 * BLOCK_PX
        from uma.mbc.block_kernels import block_sse

        truth = source[y0:y1, x0:x1]
        rows, cols = r1 - r0, c1 - c0
        sse = np.empty((len(CHOICES), rows, cols), np.float32)
        for k, candidate in enumerate(lumas):  # each block's squared luma error, compiled
            block_sse(candidate, truth, BLOCK_PX, sse[k])
        sse[barred] = np.inf
        state = self.state[r0:r1, c0:c1]
        current = np.take_along_axis(sse, state[None].astype(np.intp), 0)[0]
        gain = (current - sse.min(axis=0)).ravel()
        best = sse.argmin(axis=0).ravel()
        cost = change_bits(rows * cols)
        ranked = np.argsort(-gain, kind="stable")
        order = ranked[gain[ranked] > 0].tolist()  # the blocks that gain, most first
        n = 0
        while n < len(order) and count_bits(n + 1) + (n + 1) * cost <= self.bucket:
            n += 1
        sent = []
        for k in order[:n]:
            others = [c for c in range(len(CHOICES)) if c != state[k // cols, k % cols]]
            sent.append((k, others.index(best[k])))
            state[k // cols, k % cols] = best[k]
            self.anchor[:, r0 + k // cols, c0 + k % cols] = self._centre
        self.sent = np.array(sent, np.int64).reshape(-1, 2)
        spent = count_bits(n) + n * cost
        self.bucket -= spent
        self.bits += spent
        self.changes += n

    def _take(self, changes: np.ndarray, window, barred: np.ndarray) -> None:
        """The receiver's side: the decoded `changes` taken (their bits counted as sent)."""
        c0, r0, c1, r1 = window
        rows, cols = r1 - r0, c1 - c0
        state = self.state[r0:r1, c0:c1]
        for k, code in changes:
            if not (0 <= k < rows * cols and 0 <= code < len(CHOICES) - 1):
                raise SceneError(f"block map: change {(k, code)} outside a {rows}x{cols} window")
            r, c = divmod(int(k), cols)
            new = [n for n in range(len(CHOICES)) if n != state[r, c]][code]
            if barred[new, r, c]:
                raise SceneError(f"block map: block {k} may not show the {CHOICES[new]} now")
            state[r, c] = new
            self.anchor[:, r0 + r, c0 + c] = self._centre
        spent = count_bits(len(changes)) + len(changes) * change_bits(rows * cols)
        self.bits += spent
        self.changes += len(changes)


def _barred(face: np.ndarray, plate_known, window) -> np.ndarray:
    """(len(CHOICES), rows, cols): the choices a block of the window may not take: the plate
    and the reference where the drawn face fills the block (they are drawn only outside the
    face: an old face or the plate's guess over the face errs less than a face drawn wrong but
    looks like no face), the plate where it has not seen every pixel of the block outside the
    face, blurs where the face fills the block."""
    c0, r0, c1, r1 = window
    rows, cols = r1 - r0, c1 - c0

    def any_in_block(crop):  # the rows of a block first: a contiguous reduction, then its columns
        down = np.logical_or.reduce(crop.reshape(rows, BLOCK_PX, cols * BLOCK_PX), axis=1)
        return down.reshape(rows, cols, BLOCK_PX).any(axis=2)

    off_face = ~_window_crop(face, window)  # the window's pixels only
    out = np.zeros((len(CHOICES), rows, cols), bool)
    inside = ~any_in_block(off_face)  # the face's interior: drawn by the model, never replaced
    if plate_known is None:
        unseen = inside
    else:
        unseen = inside | any_in_block(~_window_crop(plate_known, window) & off_face)
    out[CHOICES.index("plate")] = unseen
    out[CHOICES.index("reference")] = inside
    out[CHOICES.index("softened")] = inside
    out[CHOICES.index("blurred")] = inside
    return out


def _candidates(shown, plate, reference, window, on_face) -> list[np.ndarray]:
    """The window's luma in each of `CHOICES` (uint8 crops, in order): the plate and the
    reference keep the rendering at the face's pixels `on_face` (the window's)."""
    return [_candidate(k, shown, plate, reference, window, on_face) for k in range(len(CHOICES))]


def _candidate(k: int, shown, plate, reference, window, on_face) -> np.ndarray:
    """The window's luma in choice `k` (see `_candidates`)."""
    import cv2

    height = shown.shape[0] * 2 // 3
    (y0, x0, y1, x1), (by0, bx0, by1, bx1) = _margin_box(window, (shown.shape[1], height))
    rendering = shown[y0:y1, x0:x1]
    if CHOICES[k] in ("plate", "reference"):
        held = plate if CHOICES[k] == "plate" else reference
        return np.where(on_face, rendering, held[y0:y1, x0:x1])
    if k == 0:
        return rendering
    blurred = cv2.GaussianBlur(shown[by0:by1, bx0:bx1], (0, 0), BLUR_SIGMAS_PX[k - 1])
    return blurred[y0 - by0 : y1 - by0, x0 - bx0 : x1 - bx0]


def _chroma(k: int, shown, held, window, on_face) -> np.ndarray:
    """(2, h/2, w/2): the window's chroma planes in choice `k` (`held`: the plate and the
    reference, kept off the face's pixels `on_face` as the luma is)."""
    import cv2

    height = shown.shape[0] * 2 // 3
    width = shown.shape[1]
    (y0, x0, y1, x1), (by0, bx0, by1, bx1) = _margin_box(window, (width, height))
    rows, cols = slice(y0 // 2, y1 // 2), slice(x0 // 2, x1 // 2)
    if CHOICES[k] in ("plate", "reference"):
        picture = held[0] if CHOICES[k] == "plate" else held[1]
        mine = shown[height:].reshape(2, height // 2, width // 2)[:, rows, cols]
        theirs = picture[height:].reshape(2, height // 2, width // 2)[:, rows, cols]
        return np.where(on_face[0::2, 0::2][None], mine, theirs)
    sigma = max(BLUR_SIGMAS_PX[k - 1] / 2, 0.5)
    out = []
    for plane in shown[height:].reshape(2, height // 2, width // 2):
        blurred = cv2.GaussianBlur(plane[by0 // 2 : by1 // 2, bx0 // 2 : bx1 // 2], (0, 0), sigma)
        out.append(blurred[(y0 - by0) // 2 : (y1 - by0) // 2, (x0 - bx0) // 2 : (x1 - bx0) // 2])
    return np.stack(out)


def _weights(chosen: np.ndarray, kept: dict, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The luma and chroma weights of the window's blocks `chosen` (rows, cols bool) for
    choice `k`, faded at their edges; `kept` holds each choice's last, as the blocks holding
    a choice mostly stay from one frame to the next."""
    key = chosen.tobytes(), chosen.shape
    if k in kept and kept[k][0] == key:
        return kept[k][1]
    half = np.repeat(np.repeat(chosen, BLOCK_PX // 2, axis=0), BLOCK_PX // 2, axis=1)
    whole = np.repeat(np.repeat(chosen, BLOCK_PX, axis=0), BLOCK_PX, axis=1)
    out = _feathered(whole, FEATHER_SIGMA_PX), _feathered(half, FEATHER_SIGMA_PX / 2)[None]
    kept[k] = (key, out)
    return out


def _compose(shown, lumas, state, window, held, on_face, kept: dict) -> np.ndarray:
    """`shown` with each block of the window drawn from its chosen candidate (`held`: the
    plate and the reference), the blocks' edges faded over `FEATHER_SIGMA_PX` (a copy when
    any block is not the rendering); `kept` the weights `_weights` keeps."""
    from uma.mbc.block_kernels import accumulate

    if not state.any():
        return shown
    height = shown.shape[0] * 2 // 3
    width = shown.shape[1]
    (y0, x0, y1, x1), _ = _margin_box(window, (width, height))
    out = shown.copy()
    luma = out[y0:y1, x0:x1]
    chroma = out[height:].reshape(2, height // 2, width // 2)[
        :, y0 // 2 : y1 // 2, x0 // 2 : x1 // 2
    ]
    base_luma = luma.astype(np.float32)
    base_chroma = chroma.astype(np.float32)
    mixed_luma, mixed_chroma = base_luma.copy(), base_chroma.copy()
    for k in range(1, len(CHOICES)):
        chosen = state == k
        if not chosen.any():
            continue
        weight, half_weight = _weights(chosen, kept, k)
        if lumas[k] is None:  # the receiver draws only the choices its blocks hold
            lumas[k] = _candidate(k, shown, *held, window, on_face)
        accumulate(mixed_luma, base_luma, lumas[k], weight)  # += weight (candidate - base)
        candidate = _chroma(k, shown, held, window, on_face)
        for plane in range(2):
            accumulate(mixed_chroma[plane], base_chroma[plane], candidate[plane], half_weight[0])
    for mixed, into in ((mixed_luma, luma), (mixed_chroma, chroma)):  # rounded in place
        into[:] = np.clip(np.rint(mixed, out=mixed), 0, 255, out=mixed)
    return out


def _feathered(mask: np.ndarray, sigma_px: float) -> np.ndarray:
    """`mask` (bool) as float32 weights faded over `sigma_px` at its edges (0: hard)."""
    import cv2

    weight = mask.astype(np.float32)
    if sigma_px <= 0:
        return weight
    return cv2.GaussianBlur(weight, (0, 0), sigma_px, borderType=cv2.BORDER_REPLICATE)
