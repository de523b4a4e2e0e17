"""`uma run`'s summary: per codec what it sent and how long it was on screen, per technology the
frozen share and the face's quality (names from the registry, values from metrics.json)."""

from uma.sim.summary import format_summary

BASE = {
    "scenario": "s",
    "seed": 1,
    "frames": 10,
    "video": "176x144@25",
    "source": "talking-head",
    "duration_s": 0.4,
    "switches": 0,
    "handovers": 1,
    "keyframe_requests": 0,
}


def test_a_switching_run_says_each_codecs_share_and_each_technology():
    metrics = BASE | {
        "switching": "threshold",
        "codec_switches": 2,
        "inits": 1,
        "kbps_h264": 300.0,
        "kbps_mbc": 0.6,
        "shown_s_by_codec": {"h264": 0.24, "mbc": 0.16},
        "by_technology": {
            "GSM": {"freeze_ratio": 0.05, "psnr_face_db": 20.5, "ssim_face": 0.7},
            "WLAN": {"freeze_ratio": 0.0, "psnr_face_db": None, "ssim_face": None},
        },
    }
    text = format_summary(metrics, "out")
    assert "2 codec switches, 1 model-codec initialisations" in text
    assert "H.264 300 kbit/s, on screen 0.24 s; model-based 0.6 kbit/s, on screen 0.16 s" in text
    assert "GSM       frozen 0.05, face 20.5 dB, SSIM 0.7" in text
    assert "WLAN      frozen 0\n" in text


def test_an_h264_only_run_names_no_model_codec():
    text = format_summary(BASE | {"switching": "none", "kbps_h264": 100.0, "kbps_mbc": 0.0}, "o")
    assert "codec switches" not in text and "model-based" not in text
    assert "H.264 100 kbit/s, on screen 0 s" in text
