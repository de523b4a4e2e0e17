"""Entropy coding of quantised parameter sets with constriction's range coder.

Units: symbols are quantised indices (integers, `uma.mbc.quant`); sizes in bits and 32-bit
words (constriction's stream coders write words).

An intra set codes each absolute index uniformly over 2^20 values (20 bits each: intra sets
are rare). A predictive set codes each residual index with its own parameter's adaptive
categorical model over -K..K plus an escape (then the index itself, 20 bits): constriction's
stream coders take a probability table per symbol, and the frequency counts behind the
tables are kept here, updated identically by encoder and decoder after every set. Every
intra set resets the counts to their prior (a Laplace-like shape around 0), so a decoder that
joins or resynchronises at an intra set holds exactly the encoder's models. All sets of one
packet share one range-coded stream (a queue: first in, first out), ended once, so a packet
pays the coder's flush (at most one 32-bit word) once.

With a block map (`uma.mbc.block_map`, `map_blocks` blocks in its window), each set is followed
by its frame's changes in the same stream: their count as an Exp-Golomb code (one uniform bit
each: 1 bit for none), then each change's block index (uniform over `map_blocks`) and its new
choice's code (uniform over `MAP_CODES`: which of the block's other choices); the count's bits
and the changes cost what `uma.mbc.block_map.count_bits` and `change_bits` say.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uma.mbc.errors import PacketError

__all__ = [
    "CoderConfig",
    "AdaptiveModels",
    "encode_sets",
    "decode_sets",
    "INTRA_BITS",
    "MAP_CODES",
]

INTRA_BITS = 20
MAP_CODES = 4  # a changed block's new choice: one of the other four of the map's five
_INTRA_OFFSET = 1 << (INTRA_BITS - 1)


@dataclass(frozen=True)
class CoderConfig:
    """The adaptive models: residuals in -half_range..half_range get their own symbol,
    larger ones escape; the prior's counts fall off as exp(-|k| / prior_width); every coded
    symbol adds `increment` to its count; counts halve when they sum beyond `max_total`."""

    half_range: int = 24
    prior_peak: float = 16.0
    prior_width: float = 3.0
    increment: int = 24
    max_total: int = 1 << 13

    def __post_init__(self) -> None:
        if not (1 <= self.half_range <= 255 and self.increment >= 1 and self.prior_width > 0):
            raise ValueError(f"coder: half_range 1-255, increment >= 1, width > 0: got {self}")
        if self.max_total < 4 * (2 * self.half_range + 2) or self.prior_peak < 1:
            raise ValueError(f"coder: max_total too small or prior_peak < 1: {self}")


class AdaptiveModels:
    """Frequency counts for every parameter's residual symbols (index half_range is 0;
    the last symbol is the escape)."""

    def __init__(self, n_params: int, config: CoderConfig = CoderConfig()):
        self.config = config
        self.n_params = n_params
        k = np.arange(-config.half_range, config.half_range + 1)
        prior = np.maximum(1, np.rint(config.prior_peak * np.exp(-np.abs(k) / config.prior_width)))
        self._prior = np.append(prior, 1).astype(np.int64)
        self.reset()

    def reset(self) -> None:
        self.counts = np.tile(self._prior, (self.n_params, 1))

    def probabilities(self) -> np.ndarray:
        """(P, S) float32 tables, each summing to 1."""
        counts = self.counts.astype(np.float64)
        return (counts / counts.sum(axis=1, keepdims=True)).astype(np.float32)

    def update(self, symbols: np.ndarray) -> None:
        rows = np.arange(self.n_params)
        self.counts[rows, symbols] += self.config.increment
        full = self.counts.sum(axis=1) > self.config.max_total
        if full.any():
            self.counts[full] = (self.counts[full] + 1) // 2

    def symbols(self, residuals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Category symbols of residual indices, and which of them escape."""
        h = self.config.half_range
        escape = np.abs(residuals) > h
        return np.where(escape, 2 * h + 1, residuals + h).astype(np.int32), escape


def _check_range(indices: np.ndarray) -> None:
    if np.any(np.abs(indices) >= _INTRA_OFFSET):
        raise ValueError(
            f"an index {int(np.abs(indices).max())} is beyond the coder's +-{_INTRA_OFFSET - 1}: "
            "parameters far outside any face (or a global step far too fine)"
        )


def encode_sets(sets: list[tuple], models: AdaptiveModels, map_blocks: int = 0):
    """Code quantised sets [(intra, indices (P,)), ...] in order; `models` adapt (and reset
    at each intra set) as they go. With `map_blocks` > 0 each set is (intra, indices, changes)
    and its frame's block map changes follow it ((n, 2) ints: block index, choice code; None:
    none). Returns the compressed words (uint32) and the bits used."""
    import constriction

    encoder = constriction.stream.queue.RangeEncoder()
    uniform = constriction.stream.model.Uniform(1 << INTRA_BITS)
    categorical = constriction.stream.model.Categorical(perfect=False)
    for entry in sets:
        intra, indices = entry[0], np.asarray(entry[1], dtype=np.int64)
        _check_range(indices)
        if intra:
            models.reset()
            encoder.encode((indices + _INTRA_OFFSET).astype(np.int32), uniform)
        else:
            symbols, escape = models.symbols(indices)
            encoder.encode(symbols, categorical, models.probabilities())
            if escape.any():
                encoder.encode((indices[escape] + _INTRA_OFFSET).astype(np.int32), uniform)
            models.update(symbols)
        if map_blocks:
            _encode_changes(encoder, entry[2], map_blocks)
    bits = int(encoder.num_bits())
    return encoder.get_compressed(), bits


def _checked_changes(changes, map_blocks: int) -> np.ndarray:
    """A frame's changes as (n, 2) int64; ones the map cannot send raise `ValueError`."""
    out = np.zeros((0, 2), np.int64) if changes is None else np.asarray(changes, np.int64)
    out = out.reshape(-1, 2)
    if (
        len(out) > map_blocks
        or np.any((out[:, 0] < 0) | (out[:, 0] >= map_blocks))
        or np.any((out[:, 1] < 0) | (out[:, 1] >= MAP_CODES))
        or len(np.unique(out[:, 0])) != len(out)
    ):
        raise ValueError(
            f"block map changes: distinct blocks below {map_blocks} with codes below "
            f"{MAP_CODES} expected, got {out.tolist()}"
        )
    return out


def _encode_changes(encoder, changes, map_blocks: int) -> None:
    """One frame's block map changes into the stream (see the module docstring)."""
    import constriction

    changes = _checked_changes(changes, map_blocks)
    value = len(changes) + 1
    bits = [0] * (value.bit_length() - 1) + [int(b) for b in bin(value)[2:]]
    encoder.encode(np.array(bits, np.int32), constriction.stream.model.Uniform(2))
    if len(changes):
        encoder.encode(
            changes[:, 0].astype(np.int32), constriction.stream.model.Uniform(map_blocks)
        )
        encoder.encode(changes[:, 1].astype(np.int32), constriction.stream.model.Uniform(MAP_CODES))


def _decode_changes(decoder, map_blocks: int) -> np.ndarray:
    """One frame's block map changes from the stream; a count or a block the map cannot have
    sent raises `PacketError`."""
    import constriction

    bit = constriction.stream.model.Uniform(2)
    zeros = 0
    while int(decoder.decode(bit, 1)[0]) == 0:
        zeros += 1
        if zeros > map_blocks.bit_length():
            raise PacketError(f"a block map count longer than {map_blocks} changes")
    value = 1
    for _ in range(zeros):
        value = 2 * value + int(decoder.decode(bit, 1)[0])
    count = value - 1
    if count > map_blocks:
        raise PacketError(f"{count} block map changes in a window of {map_blocks} blocks")
    if not count:
        return np.zeros((0, 2), np.int64)
    blocks = decoder.decode(constriction.stream.model.Uniform(map_blocks), count)
    codes = decoder.decode(constriction.stream.model.Uniform(MAP_CODES), count)
    if len(np.unique(blocks)) != count:
        raise PacketError(f"a block changed twice in one frame: {sorted(blocks.tolist())}")
    return np.stack([blocks, codes], axis=1).astype(np.int64)


def decode_sets(
    words: np.ndarray,
    kinds: list[bool],
    models: AdaptiveModels,
    map_blocks: int = 0,
    changes: list | None = None,
) -> list[np.ndarray]:
    """The inverse of `encode_sets` for sets of the given kinds (True: intra); with
    `map_blocks` > 0 each frame's block map changes are appended to `changes`. Data the
    models cannot have produced raises `PacketError` (its caller names the packet)."""
    import constriction

    try:
        decoder = constriction.stream.queue.RangeDecoder(np.asarray(words, dtype=np.uint32))
        uniform = constriction.stream.model.Uniform(1 << INTRA_BITS)
        categorical = constriction.stream.model.Categorical(perfect=False)
        out = []
        for intra in kinds:
            if intra:
                models.reset()
                values = decoder.decode(uniform, models.n_params).astype(np.int64)
                out.append(values - _INTRA_OFFSET)
            else:
                out.append(_decode_predictive(decoder, models, uniform, categorical))
            if map_blocks:
                changes.append(_decode_changes(decoder, map_blocks))
        return out
    except (KeyboardInterrupt, SystemExit, PacketError):
        raise
    except BaseException as err:  # constriction reports bad data as assertions or Rust panics
        raise PacketError(f"the parameter stream does not decode ({type(err).__name__})") from None


def _decode_predictive(decoder, models: AdaptiveModels, uniform, categorical) -> np.ndarray:
    """One predictive set's residual indices (the models updated)."""
    symbols = decoder.decode(categorical, models.probabilities()).astype(np.int64)
    indices = symbols - models.config.half_range
    escape = symbols == 2 * models.config.half_range + 1
    if escape.any():
        raw = decoder.decode(uniform, int(escape.sum())).astype(np.int64)
        indices[escape] = raw - _INTRA_OFFSET
    models.update(symbols)
    return indices
