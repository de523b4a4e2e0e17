"""Video: H.264, VP8 and AV1 over PyAV (libx264, libvpx, SVT-AV1 encode; FFmpeg and dav1d
decode), the rate ladders, frame sources.

Frames are planar YUV 4:2:0 arrays of shape (H * 3 // 2, W), uint8, everywhere in uma (PyAV's
`to_ndarray(format="yuv420p")` layout); luma is `frame[:H]`. PyAV and OpenCV are imported
inside the functions that need them.
"""

from uma.video.av1 import AV1Decoder, AV1Encoder, AV1Settings
from uma.video.frame import read_frame
from uma.video.h264 import NAL_IDR, EncodedFrame, H264Decoder, H264Encoder, nal_unit_types
from uma.video.ladder import (
    LADDER_CODECS,
    EncoderSettings,
    Ladder,
    Rung,
    default_ladder_path,
    load_ladder,
    open_span,
    settings_class,
)
from uma.video.pyav_codec import Retarget
from uma.video.scale import resize_yuv420, split_planes
from uma.video.sources import PatternSource, RawYuvSource, VideoFileSource
from uma.video.vp8 import VP8Decoder, VP8Encoder, VP8Settings

__all__ = [
    "H264Encoder",
    "H264Decoder",
    "EncodedFrame",
    "nal_unit_types",
    "NAL_IDR",
    "Retarget",
    "VP8Encoder",
    "VP8Decoder",
    "VP8Settings",
    "AV1Encoder",
    "AV1Decoder",
    "AV1Settings",
    "Ladder",
    "open_span",
    "Rung",
    "EncoderSettings",
    "load_ladder",
    "default_ladder_path",
    "LADDER_CODECS",
    "settings_class",
    "resize_yuv420",
    "split_planes",
    "VideoFileSource",
    "RawYuvSource",
    "PatternSource",
    "read_frame",
]
