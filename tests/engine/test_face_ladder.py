"""The face-region rungs on the rate ladder: climbed like any rung, left when no face is found."""

from uma.config import EngineConfig, EstimatorConfig, FeedbackConfig
from uma.engine import CodedReport, UmaEngine
from uma.engine.points import OperatingPoint, rate_indices
from uma.engine.policy import PolicyView, throughput_policy

# The world's order: MBC, face-region rungs, full-frame rungs.
POINTS = (
    OperatingPoint("mbc", 4.8, 25.0, 176, 144),
    OperatingPoint("h264-face", 8.0, 5.0, 64, 64),
    OperatingPoint("h264-face", 12.0, 5.0, 64, 64),
    OperatingPoint("h264", 16.0, 5.0, 128, 96),
    OperatingPoint("h264", 64.0, 12.5, 176, 144),
)


def engine(initial_kbps: float, **face):
    config = EngineConfig.model_validate(
        {
            "estimator": EstimatorConfig(
                initial_kbps=initial_kbps, min_kbps=min(5.0, initial_kbps)
            ),
            "safety": 1.0,
            "face_region": {"enabled": True} | face,
        }
    )
    return UmaEngine(
        config,
        points=POINTS,
        source_fps=25.0,
        feedback=FeedbackConfig(interval_ms=100.0),
        model_unavailable="test: no MBC",
    )


def test_rate_ladder_is_the_h264_family_by_rate():
    assert rate_indices(POINTS) == (1, 2, 3, 4)
    shuffled = (POINTS[4], POINTS[1], POINTS[3], POINTS[0], POINTS[2])
    assert [shuffled[i].rate_kbps for i in rate_indices(shuffled)] == [8.0, 12.0, 16.0, 64.0]


def test_policies_climb_the_face_rungs_like_any_rung():
    view = PolicyView(
        now_s=10.0,
        points=POINTS,
        current=4,
        last_switch_s=0.0,
        estimate_kbps=13.0,
        safety=1.0,
        up_hold_s=1.0,
    )
    assert throughput_policy(view) == 2  # 12 kbit/s fits, 16 does not
    up = PolicyView(
        now_s=10.0,
        points=POINTS,
        current=1,
        last_switch_s=0.0,
        estimate_kbps=100.0,
        safety=1.0,
        up_hold_s=1.0,
    )
    assert throughput_policy(up) == 2  # one rung at a time, the face rungs included
    assert engine(10.0).rung == 1 and engine(13.0).rung == 2 and engine(20.0).rung == 3


def test_no_face_moves_to_the_lowest_full_frame_rung_and_blocks_the_face_rungs():
    e = engine(13.0, retry_ms=2000.0)
    decision = e.on_frame(4, 0.16)
    assert decision.point.codec == "h264-face"
    e.on_coded(CodedReport(4, decision.rung, keyframe=True, failure="no face detected"), 0.2)
    assert e.rung == 3
    assert [ev.kind for ev in e.events][-2:] == ["face_region_failed", "fallback"]
    assert "no face detected" in e.events[-2].detail
    assert e.counts["face_region_failures"] == 1
    decision = e.on_frame(9, 0.36)
    assert decision.point.codec == "h264" and decision.force_idr  # a new stream
    assert e.on_frame(14, 1.5).point.codec == "h264"  # still blocked
    # After retry_ms the face rungs are back on the ladder (the estimate carries 12 kbit/s).
    later = e.on_frame(59, 2.4)
    assert later.rung in (1, 2)


def test_switching_sees_the_face_rungs_as_h264():
    # Two-level switching: on a face rung the budget above to_mbc_below_kbps keeps H.264,
    # and no MBC initialisation starts (the policy does not read "h264-face" as "not h264").
    e = engine(13.0, retry_ms=2000.0)
    config = e.config.model_copy(
        update={
            "switching": e.config.switching.model_copy(
                update={
                    "policy": "threshold",
                    "to_mbc_below_kbps": 5.0,
                    "to_h264_above_kbps": 20.0,
                    "min_dwell_ms": 0.0,
                }
            )
        }
    )
    e = UmaEngine(
        config, points=POINTS, source_fps=25.0, feedback=FeedbackConfig(interval_ms=100.0)
    )
    decisions = [e.on_frame(i, i / 25.0) for i in range(20)]
    assert all(d.point.codec == "h264-face" and d.initialise is None for d in decisions)
    assert "mbc_init_start" not in [ev.kind for ev in e.events]


def test_mbc_refused_falls_back_to_the_lowest_rung_of_the_ladder_the_face_rung():
    # No description: MBC is refused; the lowest rate-ladder rung is the 8 kbit/s face rung.
    e = engine(4.0)
    config = e.config.model_copy(
        update={"switching": e.config.switching.model_copy(update={"policy": "threshold"})}
    )
    e = UmaEngine(
        config,
        points=POINTS,
        source_fps=25.0,
        feedback=FeedbackConfig(interval_ms=100.0),
        model_unavailable="no content description",
    )
    decision = e.on_frame(4, 3.2)
    assert decision.point.codec == "h264-face" and decision.rung == 1
    assert "mbc_refused" in [ev.kind for ev in e.events]
    # With no face either, the full-frame rung: the face rungs leave the ladder.
    e.on_coded(CodedReport(4, decision.rung, keyframe=True, failure="no face detected"), 3.3)
    assert e.on_frame(9, 3.4).rung == 3
