"""`uma bench mbc` on clips made from akiyo: mirrored, halved to QCIF, under a swinging light,
rolled, a wide shot, 16:9, portrait, 15 frames/s, gray, a close-up and sensor noise.

    python scripts/mbc_transformed.py [--out DIR] [--frames N] [--only NAME ...]

writes, in DIR (default /tmp/mbc-transformed), each clip losslessly (libx264 at qp 0 through
PyAV) with the hand-clicked points of `codecs/face/akiyo.yaml` moved with it, describes it with
`uma describe`, runs `uma bench mbc --video CLIP --face CLIP.face --json --picture` on it, and
prints a table of face-box PSNR dB / SSIM and whole-frame SSIM beside akiyo's own row (from a
run of the same bench). The clips are akiyo's own frames transformed: a check of what the
defaults assume (a face turned the other way, a small face, a light the background does not
follow, a head tilted toward a shoulder, a small face in a large picture, other shapes, half
the frame rate, no colour), not a clip of a new person (docs/mbc.md, sessions 32, 33 and 35). Needs ../shared/data beside the clone. Run from the repository root.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import functools
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import yaml

AKIYO = Path("../shared/data/faces/video/akiyo.mp4")
POINTS = Path("codecs/face/akiyo.yaml")
WIDTH, HEIGHT = 352, 288
# MPEG-4 feature points named for the subject's left (odd) and right (even) in akiyo's file.
PAIRS = [("3.5", "3.6"), ("3.7", "3.8"), ("3.11", "3.12"), ("3.1", "3.2"), ("3.3", "3.4"),
         ("4.1", "4.2"), ("4.3", "4.4"), ("4.5", "4.6"), ("9.1", "9.2"), ("8.3", "8.4"),
         ("2.13", "2.14")]  # fmt: skip
DISPLAYS = ("quantised", "frozen", "h264_lowest", "av1_lowest", "mbc_refresh_lowest",
            "h264_second", "av1_second", "mbc_refresh_second")  # fmt: skip


def mirrored(bgr: np.ndarray, index: int) -> np.ndarray:
    return bgr[:, ::-1]


def qcif(bgr: np.ndarray, index: int) -> np.ndarray:
    import cv2

    return cv2.resize(bgr, (WIDTH // 2, HEIGHT // 2), interpolation=cv2.INTER_AREA)


def dim(bgr: np.ndarray, index: int) -> np.ndarray:
    """Colour times 0.85 + 0.10 sin(2 pi n / 180), plus 12 levels."""
    gain = 0.85 + 0.10 * np.sin(2 * np.pi * index / 180)
    return np.clip(bgr.astype(np.float32) * gain + 12, 0, 255).astype(np.uint8)


ROLL_PEAK_RAD = 0.5  # rolled: to 29 degrees and back over 150 frames (carphone's head: 31)


@functools.cache
def _face_centre() -> tuple[float, float]:
    """The mean of akiyo's clicked points (x, y)."""
    points = yaml.safe_load(POINTS.read_text())["points"]
    x, y = np.mean(list(points.values()), axis=0)
    return float(x), float(y)


def rolled(bgr: np.ndarray, index: int) -> np.ndarray:
    """The picture turned about akiyo's face by ROLL_PEAK_RAD sin^2(pi n / 150), its edges
    reflected: the camera rolls, so the background turns with the head (frame 0 unchanged)."""
    import cv2

    degrees = np.degrees(ROLL_PEAK_RAD) * np.sin(np.pi * index / 150) ** 2
    matrix = cv2.getRotationMatrix2D(_face_centre(), float(degrees), 1.0)
    size = (bgr.shape[1], bgr.shape[0])
    return cv2.warpAffine(bgr, matrix, size, borderMode=cv2.BORDER_REFLECT)


WIDE_OFFSET = (WIDTH // 4, HEIGHT // 4)  # where the wide shot's halved picture sits


def wide(bgr: np.ndarray, index: int) -> np.ndarray:
    """A wide shot: the picture halved and set in the middle of a grey one of the same size."""
    import cv2

    small = cv2.resize(bgr, (WIDTH // 2, HEIGHT // 2), interpolation=cv2.INTER_AREA)
    x, y = WIDE_OFFSET
    return cv2.copyMakeBorder(small, y, y, x, x, cv2.BORDER_CONSTANT, value=(90, 100, 110))


# Crops (x0, y0, width, height) of akiyo and the size each is scaled to: 16:9 and portrait.
CROPS = {
    "wide169": ((0, 45, WIDTH, 198), (640, 360)),
    "portrait": ((58, 0, 236, HEIGHT), (288, 352)),
    "closeup": ((88, 58, WIDTH // 2, HEIGHT // 2), (WIDTH, HEIGHT)),  # the face twice as large
}


def cropped(name: str):
    """The picture cut to `CROPS[name]` and scaled to its size."""
    (x0, y0, w, h), size = CROPS[name]

    def change(bgr: np.ndarray, index: int) -> np.ndarray:
        import cv2

        return cv2.resize(bgr[y0 : y0 + h, x0 : x0 + w], size, interpolation=cv2.INTER_CUBIC)

    return change


def noisy(bgr: np.ndarray, index: int) -> np.ndarray:
    """Sensor noise: Gaussian, 6 levels, drawn afresh each frame (seeded by the frame)."""
    noise = np.random.default_rng(index).normal(0.0, 6.0, bgr.shape)
    return np.clip(bgr + noise, 0, 255).astype(np.uint8)


def gray(bgr: np.ndarray, index: int) -> np.ndarray:
    import cv2

    return cv2.cvtColor(cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY), cv2.COLOR_GRAY2BGR)


def moved_points(name: str, points: dict) -> dict:
    """akiyo's points as they lie in clip `name`."""
    if name == "mirrored":
        swap = {a: b for pair in PAIRS for a, b in (pair, pair[::-1])}
        return {swap.get(k, k): [WIDTH - 1 - x, y] for k, (x, y) in points.items()}
    if name in ("qcif", "wide"):  # pixel centres halved: x' = (x + 0.5) / 2 - 0.5
        dx, dy = WIDE_OFFSET if name == "wide" else (0, 0)
        return {k: [(x + 0.5) / 2 - 0.5 + dx, (y + 0.5) / 2 - 0.5 + dy]
                for k, (x, y) in points.items()}  # fmt: skip
    if name in CROPS:
        (x0, y0, w, h), (width, height) = CROPS[name]
        return {k: [(x - x0 + 0.5) * width / w - 0.5, (y - y0 + 0.5) * height / h - 0.5]
                for k, (x, y) in points.items()}  # fmt: skip
    return dict(points)


def write_clip(path: Path, change, size: tuple[int, int], every: int = 1) -> None:
    """akiyo changed by `change` and written losslessly at `size`, every `every`-th frame (at
    its rate over `every`)."""
    import av

    with av.open(str(AKIYO)) as source, av.open(str(path), "w") as out:
        video = source.streams.video[0]
        stream = out.add_stream("libx264", rate=video.average_rate / every)
        stream.width, stream.height = size
        stream.pix_fmt = "yuv420p"
        stream.options = {"qp": "0", "preset": "ultrafast"}
        for index, frame in enumerate(source.decode(video)):
            if index % every:
                continue
            picture = np.ascontiguousarray(change(frame.to_ndarray(format="bgr24"), index))
            out.mux(stream.encode(av.VideoFrame.from_ndarray(picture, format="bgr24")))
        out.mux(stream.encode())


def bench(args: list[str]) -> dict:
    """`uma bench mbc ... --json --quiet`'s clips."""
    command = [sys.executable, "-m", "uma", "bench", "mbc", *args, "--json", "--quiet"]
    return json.loads(subprocess.run(command, check=True, capture_output=True).stdout)["clips"]


def row(name: str, clip: dict) -> str:
    face = [f"{clip['face'][d]['psnr_db']:.2f} / {clip['face'][d]['ssim']:.3f}" for d in DISPLAYS]
    frame = " / ".join(f"{clip['frame'][d]['ssim']:.3f}" for d in DISPLAYS[:3])
    tracked = f"{clip['reinits']} / {clip['lost_tracks']}"
    return f"| {name} | {tracked} | {' | '.join(face)} | {frame} |"


CLIPS = {  # name: (change, size, every other frame kept)
    "mirrored": (mirrored, (WIDTH, HEIGHT), 1),
    "qcif": (qcif, (WIDTH // 2, HEIGHT // 2), 1),
    "dim": (dim, (WIDTH, HEIGHT), 1),
    "rolled": (rolled, (WIDTH, HEIGHT), 1),
    "wide": (wide, (WIDTH, HEIGHT), 1),
    "wide169": (cropped("wide169"), CROPS["wide169"][1], 1),
    "portrait": (cropped("portrait"), CROPS["portrait"][1], 1),
    "fps15": (lambda bgr, index: bgr, (WIDTH, HEIGHT), 2),
    "gray": (gray, (WIDTH, HEIGHT), 1),
    "closeup": (cropped("closeup"), CROPS["closeup"][1], 1),
    "noisy": (noisy, (WIDTH, HEIGHT), 1),
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("/tmp/mbc-transformed"))
    parser.add_argument("--frames", type=int, default=150)
    parser.add_argument("--only", action="append", choices=sorted(CLIPS), help="one clip")
    args = parser.parse_args()
    if not AKIYO.is_file():
        print(f"mbc_transformed.py: error: {AKIYO}: not found (../shared/data)", file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    points = yaml.safe_load(POINTS.read_text())["points"]
    frames = ["--frames", str(args.frames)]
    rows = [row("akiyo", bench(frames)["akiyo"])]
    for name, (change, size, every) in CLIPS.items():
        if args.only and name not in args.only:
            continue
        clip = args.out / f"akiyo_{name}.mp4"
        write_clip(clip, change, size, every)
        clicked = {"video": clip.name, "frame": 0, "points": moved_points(name, points)}
        (args.out / f"akiyo_{name}.yaml").write_text(yaml.safe_dump(clicked))
        subprocess.run([sys.executable, "-m", "uma", "describe", "--points",
                        str(args.out / f"akiyo_{name}.yaml"), "--out", str(args.out)],
                       check=True, capture_output=True)  # fmt: skip
        result = bench(["--video", str(clip), "--face", str(clip.with_suffix(".face")),
                        "--picture", str(args.out / f"akiyo_{name}.png"), *frames])  # fmt: skip
        rows.append(row(name, next(iter(result.values()))))
    print(
        "| clip | re-inits / lost | "
        + " | ".join(DISPLAYS)
        + " | frame SSIM: MBC / frozen / H.264 16k |"
    )
    print("|---" * (len(DISPLAYS) + 3) + "|")
    print("\n".join(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
