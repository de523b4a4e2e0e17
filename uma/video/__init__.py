"""Video: H.264 over PyAV (libx264 encode, FFmpeg decode), the rate ladder, frame sources.

Frames are planar YUV 4:2:0 arrays of shape (H * 3 // 2, W), uint8, everywhere in uma (PyAV's
`to_ndarray(format="yuv420p")` layout); luma is `frame[:H]`. PyAV and OpenCV are imported
inside the functions that need them.
"""

from uma.video.frame import read_frame
from uma.video.h264 import NAL_IDR, EncodedFrame, H264Decoder, H264Encoder, nal_unit_types
from uma.video.ladder import EncoderSettings, Ladder, Rung, default_ladder_path, load_ladder
from uma.video.scale import resize_yuv420, split_planes
from uma.video.sources import PatternSource, RawYuvSource, VideoFileSource

__all__ = [
    "H264Encoder",
    "H264Decoder",
    "EncodedFrame",
    "nal_unit_types",
    "NAL_IDR",
    "Ladder",
    "Rung",
    "EncoderSettings",
    "load_ladder",
    "default_ladder_path",
    "resize_yuv420",
    "split_planes",
    "VideoFileSource",
    "RawYuvSource",
    "PatternSource",
    "read_frame",
]
