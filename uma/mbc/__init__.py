"""The model-based codec: track the personal face model, code its parameters, render them.

Pure library (no SimPy, no clock). `FaceTracker` (encoder.py) initialises and tracks;
`ParameterEncoder` (stream.py) quantises in face animation units (units.py, quant.py),
range-codes (coding.py, constriction, imported when coding) and packs (packets.py);
`ParameterDecoder` and `FaceRenderer` (decoder.py) turn packets back into pictures;
`SceneRenderer` (scene_render.py) draws the receiver's layered scene in colour: a background
plate, the torso moved by the body motion, the head by the model (layers.py,
layered_render.py); `BodyTracker` (body.py) measures the body motion at the engine;
`RefreshCoder` and `take_refresh` (refresh_coder.py) code a refresh and make it the reference
at both ends; `refresh_gain_db` and `needs_judging` (refresh_judge.py) judge one against
the receiver's rendering; `schedule_refresh` (refresh.py) says which refresh picture serves which frame.
"""

from uma.mbc.body import BodyFailure, BodyTracker
from uma.mbc.coding import AdaptiveModels, CoderConfig, decode_sets, encode_sets
from uma.mbc.decoder import Decoded, DecodeEvent, FaceRenderer, ParameterDecoder
from uma.mbc.encoder import FaceTracker, TrackerConfig, TrackFailure, TrackResult
from uma.mbc.errors import PacketError, SceneError
from uma.mbc.light import choose_head_ring
from uma.mbc.packets import IP_UDP_RTP_BYTES, Packet, parse_packet
from uma.mbc.quant import Quantiser, QuantiserConfig
from uma.mbc.refresh import RefreshSchedule, RefreshUnit, refresh_frames, schedule_refresh
from uma.mbc.refresh_coder import RefreshCoder, ResidualBox, take_refresh
from uma.mbc.refresh_judge import needs_judging, refresh_gain_db, residual_gain_db
from uma.mbc.scene_render import SceneRenderer, description_reference
from uma.mbc.stream import ParameterEncoder, StreamConfig
from uma.mbc.units import FaceUnits

__all__ = [
    "FaceTracker",
    "TrackerConfig",
    "TrackResult",
    "TrackFailure",
    "FaceUnits",
    "Quantiser",
    "QuantiserConfig",
    "CoderConfig",
    "AdaptiveModels",
    "encode_sets",
    "decode_sets",
    "Packet",
    "parse_packet",
    "IP_UDP_RTP_BYTES",
    "PacketError",
    "StreamConfig",
    "ParameterEncoder",
    "ParameterDecoder",
    "Decoded",
    "DecodeEvent",
    "FaceRenderer",
    "SceneRenderer",
    "SceneError",
    "description_reference",
    "choose_head_ring",
    "RefreshUnit",
    "RefreshSchedule",
    "refresh_frames",
    "schedule_refresh",
    "BodyTracker",
    "BodyFailure",
    "RefreshCoder",
    "take_refresh",
    "ResidualBox",
    "residual_gain_db",
    "needs_judging",
    "refresh_gain_db",
]
