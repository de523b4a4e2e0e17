"""`uma describe IMAGE|VIDEO [--frame N] --points FILE`: fit the personal wireframe to a template
picture (a still image, or one frame of a video)."""

from __future__ import annotations

import argparse

from uma.cli.args import frame_size

__all__ = ["register"]

HELP = """\
Fit the face model to a frontal template picture from feature points you clicked (a YAML or
JSON mapping of MPEG-4 feature point names, such as "3.5" for the left pupil, to [x, y]
pixels). The picture is a still image (anything OpenCV reads) or frame N of a video (anything
PyAV decodes; --frame N, 0-based). A points file may name its picture itself (video: and
frame:, or image:, as codecs/face/akiyo.yaml does); then IMAGE and --frame may be left out.
68-point iBUG landmarks serve as clicks too: a .pts file, or dlib's XML (the faces annotated
for IMAGE's file name), mapped to MPEG-4 points as uma/face/landmarks.py documents.
Writes the content description the engine sends ahead to the receiver (STEM.face, STEM the
image's or video's name: personal wireframe, texture, initial pose) and STEM.fit.png with the
fitted wireframe drawn over the picture. OpenCV's Haar cascade must find a face in it."""


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "describe",
        help="fit the face model to a template image and write its content description",
        description=HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "image",
        metavar="IMAGE|VIDEO",
        nargs="?",
        help="template image or video (default: the picture the points file names)",
    )
    parser.add_argument(
        "--frame", type=int, metavar="N", help="frame of the video (0-based; default the file's)"
    )
    parser.add_argument(
        "--points",
        required=True,
        metavar="FILE",
        help="feature points (YAML/JSON), or 68 iBUG landmarks (.pts, dlib .xml)",
    )
    parser.add_argument(
        "--face",
        type=int,
        metavar="K",
        help="with a dlib .xml naming several faces in the image: which (0-based; default the largest)",
    )
    parser.add_argument(
        "--size",
        type=frame_size,
        metavar="WxH",
        help="a raw YUV 4:2:0 clip's (.yuv) frame size, e.g. 176x144",
    )
    parser.add_argument("--model", metavar="FILE", help="face model (.yaml or Candide-3 .wfm)")
    parser.add_argument("--out", metavar="DIR", default=".", help="output folder (default .)")
    parser.set_defaults(func=handle)


def handle(args: argparse.Namespace) -> int:
    from uma.atomic import prepare_out_dir
    from uma.errors import FaceError, OutputError
    from uma.paths import check_regular_file

    # A FIFO or a device would block the readers, a symlink loop raise inside pathlib.
    for path, what in ((args.image, "image or video file"), (args.points, "points file")):
        if path is not None:
            check_regular_file(path, error=FaceError, what=what)
    if args.model is not None:
        check_regular_file(args.model, error=FaceError, what="face model file")
    prepare_out_dir(args.out)
    try:
        return _describe(args)
    except OSError as err:
        if isinstance(err, OutputError):
            raise
        where = err.filename or args.out
        raise OutputError(f"{where}: cannot write ({err.strerror or err})") from None


def _describe(args: argparse.Namespace) -> int:
    import sys
    from pathlib import Path

    import cv2

    from uma.errors import FaceError
    from uma.face import describe, load_model
    from uma.face.detect import Box, detect_faces, edge_cut_box, locate_points
    from uma.face.points import load_points

    points_file = load_points(args.points, image=args.image, face=args.face)
    points = points_file.points
    image_path, image = _picture(args, points_file)
    model = load_model(args.model) if args.model else None
    gray = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    faces, cut = detect_faces(gray), None
    if not faces:
        cut = edge_cut_box(points, gray.shape)
        if cut is None:
            raise FaceError(f"{image_path}: {faces.reason}")
        faces = [cut]
    annotated = Box(*points_file.box) if points_file.box is not None else None
    placed = locate_points(gray, points, frontal=faces, annotated=annotated)
    if not placed:
        raise FaceError(f"{args.points}: {placed.reason} (picture {image_path})")
    box, warning = placed
    result = describe(image, points, model=model)
    if not result:
        raise FaceError(f"{args.points}: {result.reason}")
    clip = _clip_frames(args, points_file, image_path)
    if clip:  # the sender's head ring for the receiver, from the clip's first second
        from uma.mbc.profile import with_sender_ring

        result = with_sender_ring(result, clip)
    out = Path(args.out)
    description_path = out / f"{image_path.stem}.face"
    size_bytes = result.save(description_path)
    png_path, zoom = _draw_fit(image, result, points, box, out / f"{image_path.stem}.fit.png")
    print(
        f"{description_path}: {size_bytes} bytes ({result.model.n_vertices} vertices, "
        f"{len(result.model.triangles)} triangles, texture {result.texture.shape[1]}x"
        f"{result.texture.shape[0]}), points fitted to {result.fit_rms_px:.2f} px rms"
    )
    scale = f", drawn {zoom}x" if zoom > 1 else ""
    print(
        f"{png_path}: fitted wireframe (green), clicked points (red), detected face (blue){scale}"
    )
    if cut is not None:
        print(f"uma: warning: {image_path}: no face detected; the points lie at the picture's "
              "edge (a face it cuts): their own box is drawn", file=sys.stderr)  # fmt: skip
    if warning is not None:
        print(f"uma: warning: {args.points}: {warning}", file=sys.stderr)
    return 0


def _picture(args: argparse.Namespace, points_file):
    """(path, BGR picture) the points belong to: IMAGE/VIDEO on the command line, else the
    points file's own."""
    from pathlib import Path

    from uma.errors import FaceError
    from uma.face.clip import picture_of, read_picture

    # A raw clip the command line names, or the points file's video: (read as a video before:
    # "neither an image OpenCV reads nor a video PyAV decodes").
    raw = args.image if args.image is not None else points_file.video
    if raw is not None and Path(raw).suffix.lower() == ".yuv":
        return Path(raw), _yuv_picture(args, points_file, raw)
    if args.image is not None:
        image_path = Path(args.image)
        # The file's frame: is of its video:, or of the one the command line names (no video:).
        own = points_file.video is None or _same(image_path, points_file.video)
        file_frame = points_file.frame if own else None
        return image_path, read_picture(image_path, frame=args.frame, video_frame=file_frame)
    source = points_file.video or points_file.image
    if source is None and points_file.frame is not None:
        raise FaceError(
            f"{args.points}: frame: {points_file.frame} given but no video: names the clip: "
            "give VIDEO"
        )
    if source is None:
        raise FaceError(f"{args.points}: names no picture: give IMAGE or VIDEO")
    return Path(str(source).removeprefix("skimage:")), picture_of(points_file, frame=args.frame)


def _clip_frames(args: argparse.Namespace, points_file, image_path) -> list:
    """The clip's YUV 4:2:0 pictures from the described frame on (`RING_FRAMES` + 1 of them),
    or [] for a still image."""
    from pathlib import Path

    from uma.face.clip import VIDEO_SUFFIXES
    from uma.mbc.profile import RING_FRAMES
    from uma.video import VideoFileSource
    from uma.video.sources import RawYuvSource

    path = Path(image_path)
    frame = args.frame if args.frame is not None else (points_file.frame or 0)
    if path.suffix.lower() == ".yuv":
        source = RawYuvSource(path, *args.size, 25.0)
    elif path.suffix.lower() in VIDEO_SUFFIXES and path.is_file():
        source = VideoFileSource(path, max_frames=frame + RING_FRAMES + 1)
    else:
        return []
    pictures = []
    for picture in source.frames():
        if len(pictures) > frame + RING_FRAMES:
            break
        pictures.append(picture)
    return pictures[frame:]


def _yuv_picture(args: argparse.Namespace, points_file, path):
    """Frame N (--frame, else the points file's, else 0) of raw YUV 4:2:0 clip `path` of
    --size, as BGR; a missing size or a frame past the clip's end is a `FaceError` naming it."""
    import cv2

    from uma.errors import FaceError
    from uma.video.sources import RawYuvSource

    if args.size is None:
        raise FaceError(f"{path}: a raw YUV clip: expected --size WxH (e.g. 176x144)")
    frame = args.frame if args.frame is not None else (points_file.frame or 0)
    for index, picture in enumerate(RawYuvSource(path, *args.size, 25.0).frames()):
        if index == frame:
            return cv2.cvtColor(picture, cv2.COLOR_YUV2BGR_I420)
    raise FaceError(f"{path}: --frame {frame}: past the clip's end ({index + 1} frames)")


def _draw_fit(image, result, points, box, png_path):
    """The fitted wireframe (green), the clicked points (red) and the detected face (blue)
    drawn on `image` into `png_path` (small pictures enlarged): (path, zoom)."""
    import cv2
    import numpy as np

    from uma.atomic import atomic_write_bytes

    # Small pictures (QCIF) are enlarged for the drawing, so the wireframe stays legible.
    zoom = max(1, int(np.ceil(ZOOM_TO_PX / max(image.shape[:2]))))
    overlay = cv2.resize(image, None, fx=zoom, fy=zoom, interpolation=cv2.INTER_CUBIC)

    def at(xy):  # pixel centres of the picture onto the enlarged drawing
        return (np.asarray(xy, dtype=np.float64) + 0.5) * zoom - 0.5

    drawn = at(result.projected() + np.array(result.origin_px)) * 16
    for triangle in result.model.triangles:
        polygon = [np.round(drawn[triangle]).astype(np.int32)]
        cv2.polylines(overlay, polygon, True, (0, 255, 0), 1, cv2.LINE_AA, 4)
    for x, y in at(list(points.values())):
        cv2.circle(overlay, (int(round(x)), int(round(y))), 2, (0, 0, 255), -1)
    corner = (box.x * zoom, box.y * zoom)
    far = ((box.x + box.width) * zoom, (box.y + box.height) * zoom)
    cv2.rectangle(overlay, corner, far, (255, 128, 0), 1)
    ok, png = cv2.imencode(".png", overlay)
    atomic_write_bytes(png_path, png.tobytes())
    return png_path, zoom


ZOOM_TO_PX = 400  # a picture smaller than this on its long side is drawn enlarged


def _same(a, b) -> bool:
    try:
        return a.resolve() == b.resolve()
    except OSError:
        return False
