"""The model-based codec's side of the codec registry (`uma.sim.codecs`): the engine's MBC
encoder (track, code, packetise), the receiver's decoder and renderer, and the selection
scheme's two halves (the sender's tracker, the engine's selecting encoder).

Units: pictures are planar YUV 4:2:0 arrays (H * 3 // 2, W) uint8; sizes in pixels; bytes out.

Both ends keep the block map (`uma.mbc.BlockMap`): the engine renders each decoded set as the
receiver will (its mirror), chooses the frame's changes against the source and sends them in
the set's packet; the receiver takes them (`BlockMap.step` at both ends). Its bits are in the
MBC's packets, so in its rate.
"""

from __future__ import annotations

import numpy as np

from uma.engine.points import OperatingPoint
from uma.mbc.profile import face_from_description, scene_renderer
from uma.sim.coded import Coded
from uma.sim.context import as_context
from uma.sim.packets import EncodedUnit

__all__ = ["MbcPointEncoder", "MbcUnitDecoder", "SenderMbc", "SelectedMbcEncoder"]


# The body motion sent changes only when the measured one moved more than this from it
# (shift px, shift px, rotation rad; docs/mbc.md "In the simulation").
BODY_HOLD = np.array([1.0, 1.0, 0.01])


def _frames(packets) -> tuple[int, ...]:
    """The source frames MBC packets carry (their first frame numbers are the run's: the
    stream is fed the run's frame indices)."""
    return tuple(f for p in packets for f in range(p.first_frame, p.first_frame + p.count))


def _luma(picture: np.ndarray) -> np.ndarray:
    return picture[: picture.shape[0] * 2 // 3]


def face_units(context):
    """The model codec's `uma.mbc.FaceUnits` in a run of `context`: the geometry, the body
    motion when the scene is layered, the light when `engine.mbc.light` is on."""
    from uma.mbc import FaceUnits

    description = context.description
    return FaceUnits.of(
        description.model, description.params, light=_light_on(context), body=context.layered
    )


def _light_on(context) -> bool:
    return context.mbc is None or context.mbc.light


def _packets_coded(packets, width: int, height: int, **more) -> Coded:
    """MBC packets as one coded unit (empty when the frame was buffered for the next)."""
    return Coded(
        b"".join(packet.to_bytes() for packet in packets),
        bool(packets and packets[0].intra),
        width,
        height,
        frames=_frames(packets),
        **more,
    )


class MbcPointEncoder:
    """The model-based codec at the engine: track the face, code its parameters, one packet
    every `frames_per_packet` frames (a frame that finishes none returns no data: it is
    buffered). `initialise` runs the automatic initialisation (the tracker's first picture)."""

    tracks = True  # this encoder tracks the face itself (the selection scheme's does not)

    def __init__(self, point: OperatingPoint, *, source_size, source_fps, settings, context):
        from uma.mbc import BodyTracker, FaceTracker, ParameterEncoder
        from uma.mbc.map_sender import MapSender

        context = as_context(context)
        description = context.description
        self.width, self.height = source_size
        if self.tracks:
            self.tracker = context.tracker or FaceTracker(description, rng=context.seed)
        self.selected = context.selected  # the selection scheme's (`SelectedMbcEncoder`)
        self.light = _light_on(context)
        self.layered = context.layered
        self.units = face_units(context)
        self.body = BodyTracker() if self.units.body else None
        self._body_sent: np.ndarray | None = None  # the body motion last sent
        self.description = description
        self.mbc = context.mbc
        self.fps = float(source_fps)
        self.map = MapSender(source_size, self.fps)
        self.stream = ParameterEncoder(self.units, context.stream, self.map.map_blocks)
        self.mirror = None  # the receiver's renderer as this encoder expects it
        self.refresh_frame = -1  # the refresh the mirror renders from (-1: none)
        self.first_params: np.ndarray | None = None  # the stream's first pose, as decoded
        self._face_from_description = True

    def set_reference(
        self, picture: np.ndarray, params: np.ndarray, *, refresh_frame: int = -1
    ) -> None:
        """Measure light against `picture` (YUV 4:2:0) with the model at `params` on it, as the
        receiver renders: by default the picture this encoder initialised on (the receiver's is
        the last it showed, at the stream's first pose); the model-aided refresh calls this
        with the refresh of `refresh_frame` the receiver took, its picture and pose, and the
        face's own triangles then come from where `engine.mbc.refresh.face` says."""
        from uma.video import resize_yuv420

        if self.mirror is None:
            self._make_mirror()
        picture = resize_yuv420(np.ascontiguousarray(picture), self.width, self.height)
        self.mirror.set_reference(picture, params)
        self._body_sent = None  # motion is from the reference: a new one starts still
        self.refresh_frame = refresh_frame
        self._face_from_description = True
        self.mirror.set_face_source(True)

    def _make_mirror(self) -> None:
        size = (self.width, self.height)
        self.mirror = scene_renderer(self.description, size, self.mbc, layered=self.layered)
        self.mirror.set_luma_only(True)  # everything the encoder decides reads luma

    def take_refresh(self, values: np.ndarray, picture, *, refresh_frame: int) -> None:
        """The receiver took refresh `refresh_frame`, its decoded `picture`
        (`uma.mbc.RefreshCoder.code`'s) at the decoded set `values` of that frame: the mirror
        takes it the same way (`uma.mbc.take_refresh`); a `uma.mbc.SceneError` if it cannot."""
        from uma.mbc import take_refresh

        if self.mirror is None:
            self._make_mirror()
        take_refresh(self.mirror, self.units, values, picture)
        self._body_sent = None
        self.refresh_frame = refresh_frame
        self._face_from_description = True
        self.mirror.set_face_source(True)

    def _face_source(self, frame: int) -> None:
        """The mirror's face from where the receiver's comes at `frame`."""
        wanted = face_from_description(self.mbc, frame, self.refresh_frame, self.fps)
        if wanted != self._face_from_description:
            self._face_from_description = wanted
            self.mirror.set_face_source(wanted)

    def decoded_params(self) -> np.ndarray | None:
        """The geometry of the last set pushed, as the receiver decodes it (None: none yet)."""
        if self.stream.decoded is None:
            return None
        return self.units.split(self.stream.decoded)[0]

    def _light(self, picture: np.ndarray, params: np.ndarray) -> tuple[float, float]:
        """The face's light on `picture` against what the receiver will render."""
        from uma.mbc.light import measure_light

        if self.mirror is None:
            self.set_reference(picture, params)
        return measure_light(self.mirror, _luma(picture), params)

    def initialise(self, picture: np.ndarray, *, frame: int):
        """A fresh track from `picture`: a `TrackResult`, or a `TrackFailure` with its reason."""
        self.tracker.reset()
        result = self.tracker.track(_luma(picture), frame=frame)
        if result:
            self.set_reference(picture, result.params)
        return result

    def _params(self, picture: np.ndarray, frame: int):
        """This frame's `TrackResult`, or a `TrackFailure` with its reason."""
        return self.tracker.track(_luma(picture), frame=frame)

    def encode(self, picture: np.ndarray, *, intra: bool, frame: int) -> Coded:
        result = self._params(picture, frame)
        if not result:
            # The open packet still goes out, short; then the engine leaves MBC.
            packets = self.stream.push(frame, None)
            self.map.count(packets)
            return _packets_coded(
                packets, self.width, self.height, evaluations=result.evaluations,
                failure=result.reason,
            )  # fmt: skip
        if intra:
            self.stream.request_intra()
        values = self._values(picture, result.params, frame)
        packets = self.stream.push(frame, values, lambda decoded: self._map(picture, decoded))
        self.map.count(packets)
        if self.first_params is None:
            self.first_params = self.decoded_params()
        return _packets_coded(
            packets, self.width, self.height, evaluations=result.evaluations,
            reinitialised=result.reinitialised,
        )  # fmt: skip

    def _values(self, picture: np.ndarray, params: np.ndarray, frame: int) -> np.ndarray:
        """The frame's set: geometry, body motion (measured against the mirror), light."""
        if self.mirror is not None:
            self._face_source(frame)
        light = self._light(picture, params) if self.light else ()
        body = ()
        if self.body is not None:
            if self.mirror is None:
                self.set_reference(picture, params)
            self.body.measure(self.mirror, _luma(picture))  # a failure keeps the last motion
            moved = self._body_sent is None or np.any(
                np.abs(self.body.last - self._body_sent) > BODY_HOLD
            )
            if moved:  # a still torso sends the same motion again: almost no bits
                self._body_sent = self.body.last.copy()
            body = self._body_sent
        return np.concatenate([params, body, light])

    def _map(self, picture: np.ndarray, decoded: np.ndarray) -> np.ndarray | None:
        """The frame's block map changes (`uma.mbc.map_sender`) against `picture`: the mirror
        drawn whole (the refresh's judge reads it then) once a refresh is taken with refreshes
        on (before that the judge draws the receiver's view; the engine's order follows)."""
        if self.mirror is None:
            self.set_reference(picture, self.units.split(decoded)[0])
        refresh = getattr(self.mbc, "refresh", None)
        whole = refresh is not None and refresh.enabled and self.refresh_frame >= 0
        return self.map.changes(self.mirror, self.units, decoded, _luma(picture), whole=whole)

    def flush(self) -> Coded:
        """The open packet, short (the engine leaves MBC)."""
        packets = self.stream.flush()
        self.map.count(packets)
        return _packets_coded(packets, self.width, self.height)


class SenderMbc:
    """The selection scheme's sender: it tracks the face in every source frame itself and sends
    each frame's parameters up with its H.264 frame (one parameter set a packet, riding in the
    same uplink packet, so only the parameter packet's own bytes are extra).

    Its compute is modelled from the tracker's evaluations (`track_us_per_evaluation`, and
    `init_us_per_evaluation` for a frame it (re-)initialised on) and reported, not simulated:
    the sender has a core for it.
    """

    def __init__(self, context, *, init_us_per_evaluation: float, track_us_per_evaluation: float):
        from dataclasses import replace

        from uma.mbc import FaceTracker, FaceUnits, ParameterEncoder

        context = as_context(context)
        description = context.description
        self.tracker = FaceTracker(description, rng=context.seed)
        units = FaceUnits.of(description.model, description.params)
        self.stream = ParameterEncoder(units, replace(context.stream, frames_per_packet=1))
        self.init_us = init_us_per_evaluation
        self.track_us = track_us_per_evaluation
        self.compute_ms = 0.0
        self.bits = 0

    def encode(self, picture: np.ndarray, *, frame: int) -> bytes:
        """The frame's parameter packet (and any open one), empty when the tracker has no face."""
        result = self.tracker.track(_luma(picture), frame=frame)
        cost_us = self.init_us if result.reinitialised else self.track_us
        self.compute_ms += cost_us * result.evaluations / 1000.0
        packets = self.stream.push(frame, result.params if result else None)
        data = b"".join(packet.to_bytes() for packet in packets)
        self.bits += 8 * len(data)
        return data


class SelectedMbcEncoder(MbcPointEncoder):
    """The selection scheme's engine side of MBC: no tracking, only a choice of stream. It
    takes the parameters the sender sent up with each frame (`CodecChain.engine_receive_mbc`
    decodes them into `CodecContext.selected`) and codes them again for the downlink (its own
    packets and intra sets, so a keyframe request is answered at once)."""

    tracks = False  # `self.selected` (`CodecContext.selected`) has the sender's parameters

    def initialise(self, picture: np.ndarray, *, frame: int):
        """Nothing to fit: ready when the sender's parameters for `frame` arrived."""
        return self._params(picture, frame, keep=True)

    def _params(self, picture: np.ndarray, frame: int, *, keep: bool = False):
        from uma.mbc.encoder import TrackFailure, TrackResult

        params = self.selected.get(frame) if keep else self.selected.pop(frame, None)
        if params is None:
            return TrackFailure("the sender's tracker has no face in this frame", frame=frame)
        return TrackResult(frame, params, 1.0, False, "selected", 0)


class MbcUnitDecoder:
    """Decodes parameter packets and renders the whole scene in colour (`uma.mbc.SceneRenderer`)
    from the last picture the receiver showed before the switch, the model placed on it at the
    stream's first decoded pose (the encoder mirrors the same choice); without such a picture,
    from the description's own. `set_reference` replaces the picture (the model-aided refresh)."""

    def __init__(self, *, context) -> None:
        from uma.mbc import ParameterDecoder
        from uma.mbc.block_map import BlockMap
        from uma.video import resize_yuv420

        context = as_context(context)
        description = context.description
        width, height = context.source_size
        self.units = face_units(context)
        self.block_map = BlockMap((width, height), float(context.fps))
        self.decoder = ParameterDecoder(self.units, context.stream, self.block_map.map_blocks)
        size = (width, height)
        self.renderer = scene_renderer(description, size, context.mbc, layered=context.layered)
        self.mbc = context.mbc
        self.fps = float(context.fps)
        self._face_from_description = context.background is not None
        self.values_by_frame: dict[int, np.ndarray] = {}  # decoded sets, for refreshes
        self.refresh_waiting: tuple[int, object] | None = None  # a refresh without its pose
        self.refresh_frame = -1  # the refresh rendered from (-1: none)
        background = context.background
        self._last: np.ndarray | None = None  # the last picture rendered
        self._pending = None
        if background is not None:
            self._pending = np.ascontiguousarray(resize_yuv420(background, width, height))
            # That picture's pose is only the stream's first: the face itself comes from the
            # description, whose pose is exact; hair, neck and background from the picture.
            self.renderer.set_face_source(True)

    def set_reference(self, picture: np.ndarray, params: np.ndarray) -> None:
        """Render from `picture` (YUV 4:2:0, source size) with the model at `params` on it;
        a `uma.mbc.SceneError` if it cannot (the old reference stays)."""
        self.renderer.set_reference(picture, params)
        self._pending = None

    def refresh(self, frame: int, picture) -> bool:
        """A model-aided refresh of `frame` decoded (`uma.mbc.RefreshCoder.code`'s picture: the
        face box with its corner): render from it at the set the stream decoded for `frame`
        (kept waiting until that set arrives). True when taken now."""
        self.refresh_waiting = (frame, picture)
        return self._take_refresh()

    def _take_refresh(self) -> bool:
        from uma.mbc import SceneError, take_refresh

        frame, picture = self.refresh_waiting
        values = self.values_by_frame.get(frame)
        if values is None:
            # Packets carry frames in order: once a later pose came, this one was lost.
            if self.values_by_frame and frame < max(self.values_by_frame):
                self.refresh_waiting = None
            return False
        self.refresh_waiting = None
        try:
            if self._pending is not None:
                self.set_reference(self._pending, self.units.split(values)[0])
            take_refresh(self.renderer, self.units, values, picture)
        except SceneError:
            return False  # the old reference stays
        self.refresh_frame = frame
        self._face_source(frame)
        return True

    def _face_source(self, frame: int) -> None:
        """The face's own triangles at `frame` from where `engine.mbc.refresh.face` says."""
        if self.refresh_frame < 0:
            return
        wanted = face_from_description(self.mbc, frame, self.refresh_frame, self.fps)
        if wanted != self._face_from_description:
            self._face_from_description = wanted
            self.renderer.set_face_source(wanted)

    def _render(self, params: np.ndarray, light, body, changes=None) -> np.ndarray:
        """The scene at the decoded set with the block map's `changes` taken; one the renderer
        or the map refuses (an absurd body motion or light, a change the map cannot take: a
        `uma.mbc.SceneError`) shows the last good picture again."""
        from uma.mbc import SceneError

        try:
            shown, face = self.renderer.render(params, light, body)
            self._last = self.block_map.step_with(self.renderer, shown, face, changes=changes)
        except SceneError:
            if self._last is None:
                self._last, _ = self.renderer.render(params, None, None)
        return self._last

    def decode(self, unit: EncodedUnit) -> dict[int, np.ndarray]:
        from uma.mbc import PacketError

        try:
            out = self.decoder.decode(unit.data)
        except PacketError:
            return {}
        # Packet frame numbers wrap (`uma.mbc.packets`); the unit knows the run's numbers.
        frames = unit.frames or (unit.frame,)
        pictures = {}
        changes = out.changes or (None,) * len(out.frames)
        for frame, (_, values), sent in zip(frames[-len(out.frames) :], out.frames, changes,
                                            strict=False):  # fmt: skip
            params, light = self.units.split(values)
            self.values_by_frame[frame] = values
            if self._pending is not None:
                self.set_reference(self._pending, params)
            if self.refresh_waiting is not None and self.refresh_waiting[0] == frame:
                self._take_refresh()
            self._face_source(frame)
            pictures[frame] = self._render(params, light, self.units.body_of(values), sent)
        for old in [f for f in self.values_by_frame if f < max(pictures or [0]) - 100]:
            del self.values_by_frame[old]
        return pictures
