"""Turn a `RunResult` into the contents of its result files."""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from uma.codecs import Role, metric_key, model_names, names, spec
from uma.metrics.aggregate import aggregate, by_technology, ssim_to_db
from uma.metrics.freezes import freeze_stats
from uma.metrics.results import events_csv, write_results
from uma.sim.world import RunResult

__all__ = ["run_metrics", "save_run", "format_summary", "shown_seconds_by_codec"]


def run_metrics(result: RunResult) -> dict[str, Any]:
    """The `metrics.json` object of a run: identification, then the aggregates."""
    head = {
        "scenario": result.scenario.name,
        "seed": result.scenario.seed,
        "source": result.source_name,
        "video": f"{result.width}x{result.height}@{result.fps:g}",
        "policy": result.scenario.engine.policy,
    }
    body = aggregate(
        result.log,
        duration_s=result.duration_s,
        capacity_bits=result.capacity.bits_until(result.duration_s),
        link=asdict(result.link),
        event_kinds=[event.kind for event in result.events],
    )
    body["by_technology"] = by_technology(result.log, display_technologies(result))
    body["feedback_lost"] = result.feedback_lost
    body |= switching_metrics(result)
    if result.scenario.engine.switching.policy != "none":
        body["shown_s_by_codec"] = shown_seconds_by_codec(result)
    if _model_section(result).refresh.enabled:
        body |= refresh_metrics(result)
    return head | body | playout_metrics(result)


def _model_section(result: RunResult):
    """The model codec's configuration section of the run's engine."""
    return getattr(result.scenario.engine, spec(model_names()[0]).config_section)


def display_technologies(result: RunResult) -> np.ndarray:
    """The access technology at each display instant (empty where none was displayed)."""
    display_ms = result.log["display_ms"]
    return np.array(
        [
            "" if not np.isfinite(t_ms) else result.capacity.technology_at(t_ms / 1000.0)
            for t_ms in display_ms.tolist()
        ],
        dtype=object,
    )


def switching_metrics(result: RunResult) -> dict[str, Any]:
    """Codec switches and the model-based codec's initialisations, failures and refusals
    (keys and event kinds named after the registry's codecs)."""
    counts = result.engine_counts or {}
    kinds = [event.kind for event in result.events]
    out: dict[str, Any] = {
        "switching": result.scenario.engine.switching.policy,
        "codec_switches": kinds.count("codec_switch"),
        "inits": counts.get("inits", 0),
        "init_failures": counts.get("init_failures", 0),
        "track_failures": counts.get("track_failures", 0),
    }
    for model in model_names():
        refused = [event.detail for event in result.events if event.kind == f"{model}_refused"]
        out["reinits"] = kinds.count(f"{model}_reinit")
        out[f"{model}_refused"] = counts.get(f"{model}_refused", 0)
        out[f"{model}_refused_reason"] = refused[0] if refused else None
    for region in names(Role.REGION):
        section = spec(region).config_section
        out[f"{section}_failures"] = counts.get(f"{section}_failures", 0)
    return out | {
        "description_bytes": result.description.size_bytes,
        "kbps_description": round(result.description.sent_bits / result.duration_s / 1000.0, 3),
        "description_delivered_s": _rounded(result.description.delivered_s),
        "description_acked_s": _rounded(result.description.acked_s),
        "description_wait_s": round(result.description.wait_s, 3),
        # The customisation scheme's costs: the engine's modelled MBC compute, and with
        # selection the sender's tracking compute and the parameters it sends up.
        "scheme": _model_section(result).scheme,
        "engine_mbc_compute_s": round(result.model.engine_compute_s, 3),
        "kbps_uplink_mbc": round(result.model.sender_bits / result.duration_s / 1000.0, 3),
        "sender_mbc_ms_per_frame": round(result.model.sender_compute_ms / result.log.frames, 3)
        if result.log.frames
        else 0.0,
    }


def refresh_metrics(result: RunResult) -> dict[str, Any]:
    """The model-aided refresh's rate (on the wire, headers included: not in `bits_sent` or
    `kbps_mbc`, which are the codecs' own), its compute and what the receiver made of it."""
    counts = result.engine_counts or {}
    return {
        "kbps_refresh": round(result.refresh.bits / result.duration_s / 1000.0, 3),
        "refresh_bits": int(result.refresh.bits),
        "refreshes": counts.get("refreshes", 0),
        "refresh_intra": counts.get("refresh_intra", 0),
        "refresh_dropped": counts.get("refresh_dropped", 0),
        "refresh_skipped": counts.get("refresh_skipped", 0),
        "refresh_decoded": result.refresh.decoded,
        "refresh_lost": result.refresh.lost,
        "refresh_adopted": counts.get("refresh_adopted", 0),
        "engine_refresh_compute_s": round(result.refresh.compute_s, 3),
    }


def _rounded(value: float | None) -> float | None:
    return None if value is None else round(value, 3)


def playout_metrics(result: RunResult) -> dict[str, Any]:
    """WebRTC's freeze statistics, displayed frame rate, playout delay and padding of a run."""
    log = result.log
    stats = freeze_stats(log["display_ms"], log["shown_frame"], duration_s=result.duration_s)
    playout_ms = log["display_ms"] - log["capture_ms"]
    playout_ms = playout_ms[np.isfinite(playout_ms)]
    stats["playout_delay_mean_ms"] = round(float(playout_ms.mean()), 3) if playout_ms.size else None
    # Salsify scores each displayed frame against its own source frame; the nearest uma has
    # without more SSIM work: the display instants that show the frame meant for them.
    fresh = log["ssim"][(log["frozen"] == 0) & np.isfinite(log["ssim"])]
    stats["ssim_db_unfrozen"] = round(ssim_to_db(float(fresh.mean())), 4) if fresh.size else None
    stats["kbps_padding"] = round(result.sent.padding / result.duration_s / 1000.0, 3)
    stats["estimator"] = result.scenario.engine.estimator.kind
    counts = result.engine_counts or {}
    # frames the rate control's skip rule left uncoded; probes of padding it sent
    stats["skipped_frames"] = counts.get("skipped_frames", 0)
    stats["probes"] = counts.get("probes", 0)
    stats["pacer_dropped_frames"] = counts.get("pacer_dropped_frames", 0)
    stats["playout"] = result.scenario.receiver.playout
    return stats


def save_run(result: RunResult, out_dir: str | Path) -> dict[str, Any]:
    """Write the run's result files atomically; returns its metrics."""
    import yaml

    metrics = run_metrics(result)
    scenario_yaml = yaml.safe_dump(result.scenario.model_dump(mode="json"), sort_keys=False)
    write_results(
        out_dir,
        scenario_yaml=scenario_yaml,
        metrics=metrics,
        frames_csv=result.log.to_csv(),
        events_csv_text=events_csv(result.events),
    )
    return metrics


def _sent(metrics: dict[str, Any]) -> str:
    """The full-frame video the run sent, named by the codec that sent it."""
    cells = [
        f"{metrics[key]:g} kbit/s {spec(name).label}"
        for name in names(Role.FULL_FRAME)
        if metrics.get(key := f"kbps_{metric_key(name)}")
    ]
    return "; ".join(cells) or "no full-frame video"


def _codec_lines(metrics: dict[str, Any]) -> list[str]:
    """What each codec sent and how long it was on screen; per technology, freezes and the face."""
    shown = metrics.get("shown_s_by_codec") or {}
    cells = []
    for name in names():
        kbps = metrics.get(f"kbps_{metric_key(name)}")
        if not kbps and name not in shown:
            continue
        cells.append(
            f"{spec(name).label} {kbps or 0:g} kbit/s, on screen {shown.get(name, 0.0):g} s"
        )
    lines = [f"  codecs    {'; '.join(cells)}"] if cells else []
    if "kbps_refresh" in metrics:
        lines.append(
            f"  refresh   {metrics['kbps_refresh']:g} kbit/s beside the model codec, "
            f"{metrics['refreshes']} refreshes ({metrics['refresh_intra']} intra), "
            f"{metrics['refresh_adopted']} taken by the receiver"
        )
    for tech, row in sorted((metrics.get("by_technology") or {}).items()):
        face = [
            f"{label} {row[key]:g}{unit}"
            for key, label, unit in (("psnr_face_db", "face", " dB"), ("ssim_face", "SSIM", ""))
            if row.get(key) is not None
        ]
        frozen = row.get("freeze_ratio")
        text = "frozen n/a" if frozen is None else f"frozen {frozen:g}"
        lines.append(f"  {tech:<9} " + ", ".join([text, *face]))
    return lines


def shown_seconds_by_codec(result: RunResult) -> dict[str, float]:
    """Seconds of display instants that showed each codec's pictures (one instant a frame)."""
    codecs = np.asarray(result.log["shown_codec"]).astype(str)
    frame_s = 1.0 / result.fps
    return {
        name: round(float(np.count_nonzero(codecs == name)) * frame_s, 3)
        for name in sorted(set(codecs.tolist()) - {""})
    }


def format_summary(metrics: dict[str, Any], out_dir: str | Path) -> str:
    """A few lines a person reads after `uma run`."""

    def show(key: str, unit: str = "") -> str:
        value = metrics.get(key)
        return "n/a" if value is None else f"{value:g}{unit}"

    switching = metrics.get("switching", "none") != "none"
    return "\n".join(
        [
            f"scenario {metrics['scenario']} (seed {metrics['seed']}): {metrics['frames']} frames"
            f" of {metrics['video']} from {metrics['source']}, {show('duration_s', ' s')}",
            f"  sent      {_sent(metrics)}, link utilisation "
            f"{show('link_utilisation')}, mean capacity {show('capacity_mean_kbps', ' kbit/s')}",
            f"  quality   PSNR {show('psnr_db', ' dB')}, SSIM {show('ssim')}"
            f" ({show('ssim_db', ' dB')})",
            f"  display   frozen {show('freeze_ratio')} of the time, delay median "
            f"{show('delay_median_ms', ' ms')}, p95 {show('delay_p95_ms', ' ms')}",
            f"  freezes   {show('freeze_count')} (WebRTC's definition), "
            f"{show('total_freezes_duration_s', ' s')} in all; {show('displayed_fps')} frames/s "
            f"shown, mean playout delay {show('playout_delay_mean_ms', ' ms')}",
            f"  engine    {metrics['switches']} rung switches, {metrics['handovers']} handovers, "
            f"{metrics['keyframe_requests']} keyframe requests"
            + (
                f", {metrics.get('codec_switches', 0)} codec switches, "
                f"{metrics.get('inits', 0)} model-codec initialisations"
                if switching
                else ""
            ),
            *_codec_lines(metrics),
            f"  results   {out_dir}",
        ]
    )
