"""Which part of the receiver's drawing makes the face box's ring err: one part changed at a time.

`python scripts/mbc_ring_parts.py [SCENARIO.yaml] [--seed N] [--every K] [--out DIR]` runs the
scenario as `uma bench headline`'s `uma` engine does and, beside the receiver's own renderer,
keeps copies of it (`VARIANTS`) that take every reference and refresh the receiver takes, each
drawing with one part of the drawing changed (a module constant, the light, the body motion,
the stretched scene; `scene_fit`, the base relit by a gain and offset fitted to the source
outside the face box). On every K-th model-codec frame it draws the decoded set with each and
scores the face box of the source frame it stands for (the face box's middle half, "middle",
and the rest, "ring": hair, neck, shoulders, background; luma PSNR of the mean squared error),
split by technology and by the age of the refresh drawn from (`<2s`, `2-6s`, `>=6s`, "none").
It prints a table and writes OUT/ring_parts.json and, for a few GSM frames, PNGs (source |
each variant). It watches the simulation: what the receiver shows is unchanged.
"""

from __future__ import annotations

from uma import __version__  # noqa: F401  (first: importing uma pins NumPy's and OpenCV's code paths)

# isort: split

import argparse
import contextlib
import copy
import json
from collections import defaultdict
from pathlib import Path

import numpy as np


@contextlib.contextmanager
def _patched(settings):
    """Module attributes set to other values for the block: ((module, name, value), ...)."""
    old = [(module, name, getattr(module, name)) for module, name, _ in settings]
    try:
        for module, name, value in settings:
            setattr(module, name, value)
        yield
    finally:
        for module, name, value in old:
            setattr(module, name, value)


def _lit_all(out, face, light, share=1.0):
    """The luma outside the face taken to the face's light (gain, offset), by `share`."""
    if light is None:
        return out
    height = face.shape[0]
    gain, offset = light
    luma = out[:height].astype(np.float32)
    lit = gain * luma + offset
    mixed = luma + share * (lit - luma)
    new = out.copy()
    new[:height] = np.where(face, out[:height], np.clip(np.rint(mixed), 0, 255)).astype(np.uint8)
    return new


def _lit_ratio(out, face, light, share=1.0):
    """The luma outside the face times the ratio of the face's lit mean to its unlit mean
    (the face's light as one multiplicative exposure), by `share`."""
    if light is None or not face.any():
        return out
    height = face.shape[0]
    gain, offset = light
    lit_mean = float(out[:height][face].mean())
    ratio = lit_mean / max((lit_mean - offset) / gain, 1.0)
    luma = out[:height].astype(np.float32)
    mixed = luma * (1.0 + share * (ratio - 1.0))
    new = out.copy()
    new[:height] = np.where(face, out[:height], np.clip(np.rint(mixed), 0, 255)).astype(np.uint8)
    return new


def _lit_gain(out, face, light):
    """The luma outside the face times the face's gain (its offset left out)."""
    if light is None:
        return out
    height = face.shape[0]
    gain, _ = light
    luma = out[:height].astype(np.float32) * gain
    new = out.copy()
    new[:height] = np.where(face, out[:height], np.clip(np.rint(luma), 0, 255)).astype(np.uint8)
    return new


def _take_inner(renderer, units, values, picture):
    """`take_refresh` whose plate learns the box less its feathered edge."""
    from uma.mbc import refresh_coder

    original = renderer.set_reference

    def set_reference(pic, params, fresh=None, camera=None):
        if fresh is not None:
            import cv2

            k = 2 * refresh_coder.FEATHER_PX + 1
            fresh = cv2.erode(fresh.astype(np.uint8), np.ones((k, k), np.uint8),
                              borderType=cv2.BORDER_REPLICATE).astype(bool)  # fmt: skip
        return original(pic, params, fresh, camera)

    renderer.set_reference = set_reference
    try:
        refresh_coder.take_refresh(renderer, units, values, picture)
    finally:
        del renderer.set_reference


def _take_over(what):
    """`take_refresh` pasting the box over the old reference itself (`what` "reference") or
    over the drawing with the torso still ("still")."""

    def take(renderer, units, values, picture):
        from uma.mbc import refresh_coder

        render = renderer.render

        def drawn(params, light=None, body=None, **kwargs):
            if what == "reference":
                return renderer.reference.copy(), None
            still = None if body is None else np.concatenate([[0.0, 0.0, 0.0], body[3:]])
            return render(params, light, still, **kwargs)

        renderer.render = drawn
        try:
            refresh_coder.take_refresh(renderer, units, values, picture)
        finally:
            del renderer.render

    return take


def _plate_margin(margin_px):
    """A `SceneRenderer._cut_layers` whose plate learns nothing within `margin_px` of the
    person."""
    from uma.mbc import scene_render

    original = scene_render.SceneRenderer._cut_layers

    def cut(self, params, fresh):
        import cv2

        update = self.plate.update

        def learn(picture, person, fresh=None):
            k = 2 * margin_px + 1
            wide = cv2.dilate(person.astype(np.uint8), np.ones((k, k), np.uint8)) > 0
            return update(picture, wide, fresh)

        self.plate.update = learn
        try:
            original(self, params, fresh)
        finally:
            del self.plate.update

    return cut


def _ref_only(adjust):
    """`adjust` where the face is drawn from the reference, not from the description."""
    return lambda out, face, light, renderer: (
        out if renderer._face_source is not None else adjust(out, face, light)
    )


def variants():
    """name -> (patch settings, render adjustment (out, face, light) -> out, body rule,
    layered, take)."""
    from uma.mbc import layered_render, layers, refresh_coder, scene_render
    from uma.mbc.scene_render import SceneRenderer

    still = lambda body: None if body is None else np.concatenate([[0, 0, 0], body[3:]])  # noqa: E731
    return {
        "base": ((), None, None, True),
        "lit_all": ((), _lit_all, None, True),
        "lit_half": ((), lambda o, f, g: _lit_all(o, f, g, 0.5), None, True),
        "lit_gain": ((), _lit_gain, None, True),
        "torso_still": ((), None, still, True),
        "feather_0": (((refresh_coder, "FEATHER_PX", 0),), None, None, True),
        "feather_24": (((refresh_coder, "FEATHER_PX", 24),), None, None, True),
        "no_bleed": (((layered_render, "FEATHER_FULL_PX", 1e9),), None, None, True),
        "stretched": ((), None, None, False),
        "lit_ratio": ((), _lit_ratio, None, True),
        "lit_ratio_half": ((), lambda o, f, g: _lit_ratio(o, f, g, 0.5), None, True),
        "lit_ref": ((), _ref_only(_lit_all), None, True),
        "lit_half_ref": ((), _ref_only(lambda o, f, g: _lit_all(o, f, g, 0.5)), None, True),
        "fresh_inner": ((), None, None, True, _take_inner),
        "paste_on_reference": ((), None, None, True, _take_over("reference")),
        "paste_torso_still": ((), None, None, True, _take_over("still")),
        "plate_margin6": (((SceneRenderer, "_cut_layers", _plate_margin(6)),), None, None, True),
        "halo_0.08": (((scene_render, "HALO_OF_HEAD", 0.08),), None, None, True),
        "hair_0.4": (((layers, "HAIR_OF_HEAD", 0.4),), None, None, True),
    }


class Fan:
    """The receiver's renderer, and copies that take the same references (each under its
    own patches)."""

    def __init__(self, main, others):
        self.main = main
        self.others = others  # name -> (renderer, settings)

    def __getattr__(self, name):
        return getattr(self.main, name)

    def set_reference(self, *args, **kwargs):
        self.main.set_reference(*args, **kwargs)
        for renderer, settings in self.others.values():
            with _patched(settings):
                renderer.set_reference(*args, **kwargs)

    def set_face_source(self, use):
        self.main.set_face_source(use)
        for renderer, _ in self.others.values():
            renderer.set_face_source(use)


def _watchers(table, every: int, drawn: dict, ages: dict):
    """The receiver's decoder methods and `take_refresh` replaced: each variant of `table`
    takes every reference and draws every `every`-th decoded set into `drawn` (by frame),
    the age of the refresh drawn from into `ages`."""
    from uma import mbc as mbc_package
    from uma.mbc.profile import scene_renderer
    from uma.sim import mbc_codecs

    cls = mbc_codecs.MbcUnitDecoder
    init, render, decode = cls.__init__, cls._render, cls.decode
    take = mbc_package.take_refresh

    def new_init(self, *, context):
        init(self, context=context)
        context = mbc_codecs.as_context(context)
        others = {}
        for name, (settings, _, _, layered, *_) in table.items():
            if layered:
                other = copy.deepcopy(self.renderer)
            else:
                other = scene_renderer(context.description, self.renderer.size, context.mbc,
                                       layered=False)  # fmt: skip
                other.set_face_source(self._face_from_description)
            others[name] = (other, settings)
        self.renderer = Fan(self.renderer, others)
        self._stash = []

    def new_take(renderer, units, values, picture):
        if not isinstance(renderer, Fan):
            return take(renderer, units, values, picture)
        take(renderer.main, units, values, picture)
        for name, (other, settings) in renderer.others.items():
            entry = table[name]
            with _patched(settings):
                (entry[4] if len(entry) > 4 else take)(other, units, values, picture)

    def new_render(self, params, light, body, changes=None):
        self._stash.append((params, light, body))
        return render(self, params, light, body, changes)

    def new_decode(self, unit):
        self._stash = []
        pictures = decode(self, unit)
        for frame, (params, light, body) in zip(pictures, self._stash, strict=False):
            if frame % every == 0:
                ages[frame] = _age(frame, self.refresh_frame, self.fps)
                drawn[frame] = _draw_variants(self.renderer, table, params, light, body)
        return pictures

    return ((cls, "__init__", new_init), (cls, "_render", new_render),
            (cls, "decode", new_decode), (mbc_package, "take_refresh", new_take))  # fmt: skip


def _age(frame: int, taken: int, fps: float) -> str:
    age_s = (frame - taken) / fps
    if taken < 0:
        return "none"
    return "<2s" if age_s < 2 else ("2-6s" if age_s < 6 else ">=6s")


def _draw_variants(fan: Fan, table, params, light, body) -> dict[str, np.ndarray]:
    """Each variant's luma at the decoded set."""
    out = {}
    for name, (settings, adjust, body_rule, *_) in table.items():
        renderer = fan.others[name][0]
        b = body if body_rule is None else body_rule(body)
        with _patched(settings):
            picture, face = renderer.render(params, light, b)
        if adjust is not None:
            picture = (adjust(picture, face, light, renderer) if name.endswith("_ref")
                       else adjust(picture, face, light))  # fmt: skip
        out[name] = picture[: fan.size[1]].copy()
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", nargs="?", default="scenarios/stockholm-uppsala.yaml")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--every", type=int, default=5)
    parser.add_argument("--only", default="", help="comma-separated variant names")
    parser.add_argument("--out", default="/tmp/mbc_ring_parts")
    args = parser.parse_args(argv)
    from uma.bench.headline import engine_scenario
    from uma.config.load import load_scenario
    from uma.sim import run_scenario
    from uma.sim.summary import display_technologies

    table = variants()
    if args.only:
        table = {k: v for k, v in table.items() if k in args.only.split(",") or k == "base"}
    scenario = load_scenario(Path(args.scenario)).model_copy(update={"seed": args.seed})
    scenario = engine_scenario(scenario, "uma")
    drawn: dict[int, dict[str, np.ndarray]] = {}
    ages: dict[int, str] = {}
    sources: dict[int, np.ndarray] = {}

    def on_display(index, source, shown, picture):
        if index % args.every == 0:
            sources[index] = source[: source.shape[0] * 2 // 3].copy()

    with _patched(_watchers(table, args.every, drawn, ages)):
        result = run_scenario(scenario, on_display=on_display)
    techs = display_technologies(result)
    return report(args, table, drawn, ages, sources, techs, result.face_boxes)


def _errors(source, picture, box):
    x0, y0, w, h = int(box.x), int(box.y), int(box.width), int(box.height)
    err = (source[y0 : y0 + h, x0 : x0 + w].astype(float) - picture[y0 : y0 + h, x0 : x0 + w]) ** 2
    inner = np.zeros(err.shape, bool)
    inner[h // 4 : h - h // 4, w // 4 : w - w // 4] = True
    return float(err.mean()), float(err[inner].mean()), float(err[~inner].mean())


def _scene_fit(source, picture, box):
    """The base drawing relit by a gain and offset fitted to the source outside the face box
    (a scene light an engine could measure and send), all but the box's middle half."""
    x0, y0, w, h = int(box.x), int(box.y), int(box.width), int(box.height)
    outside = np.ones(source.shape, bool)
    outside[y0 : y0 + h, x0 : x0 + w] = False
    drawn = picture[outside].astype(float)
    design = np.stack([drawn, np.ones_like(drawn)], axis=1)
    (gain, offset), *_ = np.linalg.lstsq(design, source[outside].astype(float), rcond=None)
    lit = np.clip(np.rint(gain * picture.astype(float) + offset), 0, 255).astype(np.uint8)
    lit[y0 + h // 4 : y0 + h - h // 4, x0 + w // 4 : x0 + w - w // 4] = picture[
        y0 + h // 4 : y0 + h - h // 4, x0 + w // 4 : x0 + w - w // 4
    ]
    return lit


def _db(values):
    return round(float(10 * np.log10(255.0**2 / max(np.mean(values), 1e-9))), 2)


def report(args, table, drawn, ages, sources, techs, boxes) -> int:
    import cv2

    out_dir = Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows: dict[tuple, dict[str, list]] = defaultdict(lambda: defaultdict(list))
    pngs = 0
    maps, counts = {}, {}
    for frame, pictures in sorted(drawn.items()):
        if frame not in sources or frame >= len(boxes) or boxes[frame] is None:
            continue
        key = (str(techs[frame]), ages[frame])
        if key == ("GSM", ">=6s"):
            for name, picture in pictures.items():
                err = (sources[frame].astype(float) - picture) ** 2
                maps[name] = maps.get(name, 0) + err
                counts[name] = counts.get(name, 0) + 1
        fitted = _scene_fit(sources[frame], pictures["base"], boxes[frame])
        pictures = {**pictures, "scene_fit": fitted}
        for name, picture in pictures.items():
            rows[key][name].append(_errors(sources[frame], picture, boxes[frame]))
        if key == ("GSM", ">=6s") and pngs < 4 and frame % (args.every * 40) == 0:
            strip = np.concatenate([sources[frame]] + list(pictures.values()), axis=1)
            cv2.imwrite(str(out_dir / f"parts-{frame:05d}.png"), strip)
            pngs += 1
    for name, total in maps.items():
        rms = np.sqrt(total / counts[name])
        cv2.imwrite(str(out_dir / f"rms-GSM-{name}.png"), np.clip(rms * 4, 0, 255).astype(np.uint8))
    result = {}
    print("tech age | n | variant: box / middle / ring dB")
    for key in sorted(rows):
        entry = {}
        for name, errs in rows[key].items():
            e = np.array(errs)
            entry[name] = {"box": _db(e[:, 0]), "middle": _db(e[:, 1]), "ring": _db(e[:, 2]),
                           "n": len(errs)}  # fmt: skip
        result[" ".join(key)] = entry
        print(f"{key[0]} {key[1]} | {len(rows[key]['base'])} | " + "; ".join(
            f"{n} {v['box']}/{v['middle']}/{v['ring']}" for n, v in entry.items()))  # fmt: skip
    (out_dir / "ring_parts.json").write_text(json.dumps(result, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
