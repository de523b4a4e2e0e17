"""MPEG-4 face animation parameters (FAPs): the ASCII `.fap` file.

Units: FAP values are integers in face animation parameter units (FAPUs): ES, ENS, MNS, MW and
IRISD are a neutral-face distance / 1024 (ISO/IEC 14496-2, Annex C), AU is 1e-5 rad.

File layout (as FBK-irst's XfaceEd and the shared files write it): a header line
`version name fps frames` (the name may hold spaces; it is what lies between the first token
and the last two), then per frame a mask line of 68 flags 0/1 (FAP 1 first) and a value line:
the frame number, then the values of the FAPs whose flag is 1, in FAP order. Lines starting
with `#` and blank lines are skipped. FAPs 1 and 2 (viseme, expression) are kept as single
numbers like the others; a file giving them as the standard's multi-value records does not
match its mask and is refused.

The mapping of FAPs onto uma's model is `uma.face.fap_map`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from uma.errors import FaceError

__all__ = [
    "N_FAPS",
    "FAP_NAMES",
    "FAP_UNITS",
    "MAX_DISTANCE_FAPU",
    "MAX_ANGLE_AU",
    "MIN_FPS",
    "MAX_FPS",
    "fap_limit",
    "FapSequence",
    "read_fap",
    "parse_fap",
    "write_fap",
    "format_fap",
]

N_FAPS = 68

# ISO/IEC 14496-2 Annex C, FAPs 1-68.
FAP_NAMES: dict[int, str] = dict(
    enumerate(
        [
            "viseme",
            "expression",
            "open_jaw",
            "lower_t_midlip",
            "raise_b_midlip",
            "stretch_l_cornerlip",
            "stretch_r_cornerlip",
            "lower_t_lip_lm",
            "lower_t_lip_rm",
            "raise_b_lip_lm",
            "raise_b_lip_rm",
            "raise_l_cornerlip",
            "raise_r_cornerlip",
            "thrust_jaw",
            "shift_jaw",
            "push_b_lip",
            "push_t_lip",
            "depress_chin",
            "close_t_l_eyelid",
            "close_t_r_eyelid",
            "close_b_l_eyelid",
            "close_b_r_eyelid",
            "yaw_l_eyeball",
            "yaw_r_eyeball",
            "pitch_l_eyeball",
            "pitch_r_eyeball",
            "thrust_l_eyeball",
            "thrust_r_eyeball",
            "dilate_l_pupil",
            "dilate_r_pupil",
            "raise_l_i_eyebrow",
            "raise_r_i_eyebrow",
            "raise_l_m_eyebrow",
            "raise_r_m_eyebrow",
            "raise_l_o_eyebrow",
            "raise_r_o_eyebrow",
            "squeeze_l_eyebrow",
            "squeeze_r_eyebrow",
            "puff_l_cheek",
            "puff_r_cheek",
            "lift_l_cheek",
            "lift_r_cheek",
            "shift_tongue_tip",
            "raise_tongue_tip",
            "thrust_tongue_tip",
            "raise_tongue",
            "tongue_roll",
            "head_pitch",
            "head_yaw",
            "head_roll",
            "lower_t_midlip_o",
            "raise_b_midlip_o",
            "stretch_l_cornerlip_o",
            "stretch_r_cornerlip_o",
            "lower_t_lip_lm_o",
            "lower_t_lip_rm_o",
            "raise_b_lip_lm_o",
            "raise_b_lip_rm_o",
            "raise_l_cornerlip_o",
            "raise_r_cornerlip_o",
            "stretch_l_nose",
            "stretch_r_nose",
            "raise_nose",
            "bend_nose",
            "raise_l_ear",
            "raise_r_ear",
            "pull_l_ear",
            "pull_r_ear",
        ],
        start=1,
    )
)


# ISO/IEC 14496-2 Annex C: the unit of each FAP (FAPs 1 and 2, viseme and expression, have none).
FAP_UNITS: dict[int, str] = {
    **{k: "MNS" for k in (3, 4, 5, 8, 9, 10, 11, 12, 13, 14, 16, 17, 18, 44, 46)},
    **{k: "MW" for k in (6, 7, 15, 43, 45, 53, 54)},
    **{k: "IRISD" for k in (19, 20, 21, 22, 29, 30)},
    **{k: "AU" for k in (23, 24, 25, 26, 47, 48, 49, 50)},
    **{k: "ES" for k in (27, 28, 37, 38, 39, 40)},
    **{k: "ENS" for k in (31, 32, 33, 34, 35, 36, 41, 42, 61, 62, 63, 64, 65, 66, 67, 68)},
    **{k: "MNS" for k in (51, 52, 55, 56, 57, 58, 59, 60)},
    1: "",
    2: "",
}
# What a face can do, generously: no feature point moves by more than four times the neutral
# distance its unit measures (a jaw opened four mouth-nose separations), no angle exceeds half a
# turn. The shared XfaceEd files stay below 900 distance units and 0.09 rad. Far larger values
# are not expressions but damage, and they overflow the renderer's polygons.
MAX_DISTANCE_FAPU = 4 * 1024
MAX_ANGLE_AU = 314159  # pi rad in units of 1e-5 rad
# Frame rates a .fap file may give: from one frame per 100 s to a fast camera's 1000 frames/s.
MIN_FPS, MAX_FPS = 0.01, 1000.0
MAX_FAP_BYTES = 64 * 1024 * 1024  # an hour at 25 frames/s with every FAP set is about 50 MB


def fap_limit(number: int) -> int:
    """The largest |value| FAP `number` may take (see `MAX_DISTANCE_FAPU`, `MAX_ANGLE_AU`)."""
    return MAX_ANGLE_AU if FAP_UNITS.get(number) == "AU" else MAX_DISTANCE_FAPU


def _value_problem(number: int, value: int) -> str | None:
    """Why `value` is beyond what a face can do for FAP `number`, or None."""
    limit = fap_limit(number)
    if abs(value) <= limit:
        return None
    unit = FAP_UNITS.get(number) or "unit"
    reason = "half a turn" if unit == "AU" else "four times the neutral distance"
    return (
        f"FAP {number} ({FAP_NAMES[number]}): expected at most {limit} {unit} in magnitude "
        f"({reason}), got {value}"
    )


def _fps_ok(fps: float) -> bool:
    return bool(np.isfinite(fps) and MIN_FPS <= fps <= MAX_FPS)


@dataclass(frozen=True)
class FapSequence:
    """A `.fap` file: per frame, FAP number (1-68) -> value (integer FAPUs)."""

    name: str
    fps: float
    frames: tuple[dict[int, int], ...]
    numbers: tuple[int, ...] = ()  # each frame's number as the file gives it (default 0, 1, ...)
    version: str = "2.1"

    def __post_init__(self) -> None:
        frames = tuple({int(k): int(v) for k, v in sorted(f.items())} for f in self.frames)
        numbers = tuple(int(n) for n in self.numbers) or tuple(range(len(frames)))
        if len(numbers) != len(frames):
            raise FaceError(f"{self.name}: {len(frames)} frames but {len(numbers)} frame numbers")
        if not _fps_ok(self.fps):
            raise FaceError(
                f"{self.name}: expected a frame rate of {MIN_FPS:g}-{MAX_FPS:g} frames/s, "
                f"got {self.fps}"
            )
        for index, frame in enumerate(frames):
            bad = [k for k in frame if not 1 <= k <= N_FAPS]
            if bad:
                raise FaceError(f"{self.name}: FAP {bad[0]} is not among 1-{N_FAPS}")
            for number, value in frame.items():
                problem = _value_problem(number, value)
                if problem is not None:
                    raise FaceError(f"{self.name}: frame {index}: {problem}")
        if not self.name.strip() or any(c in self.name for c in "\r\n"):
            raise FaceError(f"expected a one-line, non-empty name, got {self.name!r}")
        if not self.version or any(c.isspace() for c in self.version):
            raise FaceError(f"{self.name}: expected a version without spaces, got {self.version!r}")
        object.__setattr__(self, "frames", frames)
        object.__setattr__(self, "numbers", numbers)
        object.__setattr__(self, "fps", float(self.fps))

    def __len__(self) -> int:
        return len(self.frames)


def parse_fap(text: str, *, where: str = "<fap>") -> FapSequence:
    """A `FapSequence` from `.fap` text; a malformed line is a `FaceError` naming `where` and
    the line."""
    rows = [
        (k + 1, line.strip())
        for k, line in enumerate(text.splitlines())
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not rows:
        raise FaceError(f"{where}:1: expected the header 'version name fps frames', got nothing")
    number, header = rows[0]
    version, name, fps, count = _header(header, number, where)
    body = rows[1:]
    if len(body) % 2:
        number, line = body[-1]
        raise FaceError(f"{where}:{number}: a mask line without its value line")
    if len(body) // 2 != count:
        last = body[-1][0] if body else number
        raise FaceError(
            f"{where}:{last}: the header says {count} frames, the file holds {len(body) // 2}"
        )
    frames, numbers = [], []
    for mask, value in zip(body[::2], body[1::2], strict=True):
        frame_number, frame = _frame(mask, value, where)
        numbers.append(frame_number)
        frames.append(frame)
    try:
        return FapSequence(
            name=name or "unnamed",
            fps=fps,
            frames=tuple(frames),
            numbers=tuple(numbers),
            version=version,
        )
    except FaceError as err:
        raise FaceError(f"{where}: {err}") from None


def _header(header: str, number: int, where: str) -> tuple[str, str, float, int]:
    """(version, name, fps, frames) of the header line `header` (line `number`)."""
    fields = header.split()
    try:
        if len(fields) < 4:
            raise ValueError
        fps, count = float(fields[-2]), int(fields[-1])
        if count < 0:
            raise ValueError
    except ValueError:
        raise FaceError(
            f"{where}:{number}: expected the header 'version name fps frames' (frames >= 0), "
            f"got {_short(header)}"
        ) from None
    if not _fps_ok(fps):
        raise FaceError(
            f"{where}:{number}: expected a frame rate of {MIN_FPS:g}-{MAX_FPS:g} frames/s in "
            f"the header, got {fields[-2]}"
        )
    return fields[0], " ".join(fields[1:-2]), fps, count


def _frame(mask, value, where: str) -> tuple[int, dict[int, int]]:
    """(frame number, {FAP: value}) of one frame's mask line and value line, each
    (line number, text)."""
    (mask_no, mask_line), (value_no, value_line) = mask, value
    flags = mask_line.split()
    if len(flags) != N_FAPS or any(f not in ("0", "1") for f in flags):
        raise FaceError(
            f"{where}:{mask_no}: expected a mask of {N_FAPS} flags 0/1, got "
            f"{len(flags)} fields ({_short(mask_line)})"
        )
    on = [k + 1 for k, f in enumerate(flags) if f == "1"]
    try:
        values = [int(v) for v in value_line.split()]
    except ValueError:
        raise FaceError(
            f"{where}:{value_no}: expected whole numbers (frame number, then FAP values), "
            f"got {_short(value_line)}"
        ) from None
    if len(values) != len(on) + 1:
        raise FaceError(
            f"{where}:{value_no}: expected the frame number and {len(on)} values (the mask "
            f"on line {mask_no} has {len(on)} flags set), got {len(values)} numbers"
        )
    for fap, v in zip(on, values[1:], strict=True):
        problem = _value_problem(fap, v)
        if problem is not None:
            raise FaceError(f"{where}:{value_no}: {problem}")
    return values[0], dict(zip(on, values[1:], strict=True))


def _short(line: str, limit: int = 40) -> str:
    return repr(line if len(line) <= limit else line[:limit] + "...")


def read_fap(path: str | Path) -> FapSequence:
    """Read a `.fap` file (see the module docstring for the layout)."""
    from uma.errors import FaceError
    from uma.paths import read_capped

    path = Path(path)
    data = read_capped(path, max_bytes=MAX_FAP_BYTES, error=FaceError, what=".fap file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")  # names written on Windows
    return parse_fap(text, where=str(path))


def format_fap(sequence: FapSequence) -> str:
    """The `.fap` text of `sequence`: the FAPs each frame gives, and only those, flagged."""
    lines = [f"{sequence.version} {sequence.name} {sequence.fps:g} {len(sequence)}"]
    for number, frame in zip(sequence.numbers, sequence.frames, strict=True):
        lines.append(" ".join("1" if k in frame else "0" for k in range(1, N_FAPS + 1)))
        lines.append(" ".join(str(v) for v in (number, *frame.values())))
    return "\n".join(lines) + "\n"


def write_fap(sequence: FapSequence, path: str | Path) -> None:
    """Write `sequence` as a `.fap` file, atomically."""
    from uma.atomic import atomic_write_text

    atomic_write_text(path, format_fap(sequence))
