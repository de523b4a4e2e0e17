"""What `uma bench mbc` scores: the displays it compares, the regions it scores them in.

Units: PSNR in dB (luma, and chroma: Cb and Cr together), SSIM on luma (scikit-image, the
simulation's), kbit/s at the clip's own frame rate. Pictures are YUV 4:2:0 (H * 3 // 2, W).

Regions: `face`, the face box of `uma.face.region` (the simulation's: ground-truth points plus
10 % on the talking head, OpenCV's detector on a file, the last box held where it finds none);
`frame`, the whole picture; `model`, the pixels the model covers at the tracked (or true)
parameters. H.264's displays are real libx264 at a rung of the ladder, decoded and upscaled to
the source size, each picture held until the next, as the receiver shows them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["RegionSums", "codec_display", "face_box", "REGIONS"]

REGIONS = ("face", "frame", "model")


def codec_display(
    frames: list[np.ndarray], fps: float, rung_index: int, codec: str, *, delayed: bool = False
) -> tuple[list[np.ndarray], float, str]:
    """A full-frame codec's display (looked up in `uma.codecs`: its ladder file's encoder
    settings, its `uma.video` classes) at the size, frame rate and rate of the codec's own
    ladder rung `rung_index` (every ladder has H.264's rungs), at the source size (YUV 4:2:0),
    its measured rate (kbit/s) and label. `delayed`: each picture shows from the first frame
    after its bits arrive over a channel of the rung's rate (`uma.mbc.refresh`, as the
    refresh's pictures), frame 0 until then."""
    import uma.video
    from uma.codecs import spec
    from uma.mbc.refresh import RefreshUnit, schedule_refresh
    from uma.paths import codecs_dir
    from uma.video import load_ladder, resize_yuv420

    traits = spec(codec)
    ladder = load_ladder(codecs_dir() / traits.ladder)
    rung = ladder.rungs[rung_index]
    height = frames[0].shape[0] * 2 // 3
    width = frames[0].shape[1]
    step = max(1, int(round(fps / rung.fps)))
    encoder = getattr(uma.video, traits.video_encoder)(
        rung.width, rung.height, rung.fps, rung.rate_kbps, **ladder.encoder.kwargs()
    )
    decoder = getattr(uma.video, traits.video_decoder)()
    grey = np.full((height * 3 // 2, width), 128, np.uint8)
    shown, bits, last, units, pictures = [], 0, None, [], []
    for index, frame in enumerate(frames):
        if index % step == 0:
            unit = encoder.encode(resize_yuv420(frame, rung.width, rung.height))
            bits += unit.size_bits
            units.append(RefreshUnit(index, unit.size_bits, unit.is_keyframe))
            picture = decoder.decode(unit.data)
            if picture is not None:
                last = resize_yuv420(picture, width, height)
            pictures.append(last if last is not None else grey)
        shown.append(last if last is not None else grey)
    coded = -(-len(frames) // step)
    kbps = bits / (coded / rung.fps) / 1000.0
    if delayed:
        serving = schedule_refresh(units, len(frames), fps, rung.rate_kbps).serving
        shown = [frames[0] if k < 0 else pictures[k] for k in serving]
    return shown, kbps, rung.label


def face_box(luma: np.ndarray, truth_points: np.ndarray | None, last):
    """The face box (`uma.face.detect.Box`) of one frame as `uma.face.region` finds it."""
    from uma.face.region import points_box

    height, width = luma.shape
    if truth_points is not None:
        return points_box(truth_points, width, height)
    from uma.face.detect import detect_face

    found = detect_face(np.ascontiguousarray(luma))
    return found if found else last


def _psnr(mse: float) -> float:
    from uma.metrics.quality import PSNR_CAP_DB

    return PSNR_CAP_DB if mse <= 255.0**2 * 1e-10 else float(10 * np.log10(255.0**2 / mse))


@dataclass
class RegionSums:
    """Running sums of one display's scores per region; `add` one frame, `means` at the end."""

    sums: dict = field(default_factory=lambda: {r: np.zeros(3) for r in REGIONS})
    count: int = 0

    def add(self, truth: np.ndarray, shown: np.ndarray, box, model_mask: np.ndarray) -> None:
        """Score `shown` against `truth` (YUV 4:2:0): one SSIM map serves every region."""
        from skimage.metrics import structural_similarity

        height = truth.shape[0] * 2 // 3
        ref = truth.astype(np.float32)
        tst = shown.astype(np.float32)
        diff = (ref - tst) ** 2
        luma_diff, chroma_diff = diff[:height], diff[height:]
        _, ssim_map = structural_similarity(ref[:height], tst[:height], data_range=255.0, full=True)
        width = truth.shape[1]
        chroma = chroma_diff.reshape(2, height // 2, width // 2)
        face = np.zeros((height, width), bool)
        if box is not None:
            face[box.y : box.y + box.height, box.x : box.x + box.width] = True
        else:
            face[:] = True
        masks = {
            "face": face,
            "frame": np.ones_like(face),
            "model": model_mask if model_mask.any() else face,
        }
        for region, mask in masks.items():
            half = mask[0::2, 0::2]
            self.sums[region] += (
                _psnr(float(luma_diff[mask].mean())),
                float(ssim_map[mask].mean()),
                _psnr(float(chroma[:, half].mean())),
            )
        self.count += 1

    def means(self, kbps: float | None) -> dict:
        """Per region: psnr_db, ssim, chroma_psnr_db (and kbps where the display has a rate)."""
        out = {}
        for region, total in self.sums.items():
            mean = total / max(self.count, 1)
            out[region] = {
                "psnr_db": round(float(mean[0]), 3),
                "ssim": round(float(mean[1]), 4),
                "chroma_psnr_db": round(float(mean[2]), 3),
            }
            if kbps is not None:
                out[region]["kbps"] = round(float(kbps), 3)
        return out
