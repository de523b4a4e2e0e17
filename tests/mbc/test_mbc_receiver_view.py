"""The simulation's MBC receiver: the whole scene in colour from the last picture shown."""

import numpy as np

from uma.face.talking_head import Motion, TalkingHeadSource
from uma.mbc import ParameterEncoder, StreamConfig
from uma.sim.mbc_codecs import MbcUnitDecoder
from uma.sim.packets import EncodedUnit


def test_receiver_renders_colour_from_the_last_picture() -> None:
    import cv2

    head = TalkingHeadSource(176, 144, seed=2, motion=Motion(noise_std=0.0))
    frames = [cv2.cvtColor(head.render_bgr(i), cv2.COLOR_BGR2YUV_I420) for i in range(9)]
    context = {
        "description": head.description,
        "source_size": (176, 144),
        "stream": StreamConfig(frames_per_packet=4),
        "background": frames[0],
    }
    decoder = MbcUnitDecoder(context=context)
    units = decoder.units  # the simulation's: geometry, body motion, light
    assert units.body and units.light
    encoder = ParameterEncoder(units, context["stream"], decoder.block_map.map_blocks)
    packets = []
    for i in range(1, 9):
        packets += encoder.push(i, np.concatenate([head.params_at(i), np.zeros(3), (1.0, 0.0)]))
    shown = {}
    for seq, packet in enumerate(packets):
        frames_of = tuple(range(packet.first_frame, packet.first_frame + packet.count))
        unit = EncodedUnit(seq, frames_of[-1], "mbc", 0, 176, 144, packet.intra,
                           packet.to_bytes(), frames_of)  # fmt: skip
        shown.update(decoder.decode(unit))
    assert sorted(shown) == list(range(1, 9))
    first = shown[1]
    # The stream's first pose is the reference's: around the face, frame 1 is the last picture
    # unchanged; the face itself comes from the description (its pose there is exact).
    _, face = decoder.renderer.render(decoder.renderer.reference_params)
    assert face.any() and np.array_equal(first[:144][~face], frames[0][:144][~face])
    later = shown[8].astype(np.float64)
    truth = frames[8].astype(np.float64)
    chroma_error = np.sqrt(np.mean((later[144:] - truth[144:]) ** 2))
    held_error = np.sqrt(np.mean((frames[0][144:].astype(np.float64) - truth[144:]) ** 2))
    assert chroma_error < held_error  # the face's colours moved with it
    corrupt = EncodedUnit(99, 9, "mbc", 0, 176, 144, False, b"\x00" * 20, (9,))
    assert decoder.decode(corrupt) == {}  # a bad unit changes nothing on screen
