"""The timeline of one run as a PNG: capacity and technology, estimate, bit rate, quality, freezes.

Units: time in seconds on the x axis; rates in kbit/s (log scale); PSNR in dB; delay in ms (log
scale). Five panels share the time axis: (1) the trace's capacity over coloured technology
bands, the engine's estimate and the bit rate sent per codec (1 s windows); (2) displayed PSNR
with frozen display instants marked; (3) each frame's capture-to-display delay beside the least
its link allowed any engine (`uma.metrics.link_bound`, a 40-byte packet alone on the link,
when the run's scenario.yaml still loads: its traces where they were); (4) the bytes waiting in
the bottleneck's queue and in the engine's own (its pacer), when the run logged them; (5) the
rung, with rung switches, handovers and keyframe requests.
Drawn with matplotlib's object API on the Agg canvas (no global pyplot state, no display).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uma.codecs import REGISTRY, metric_key, model_names
from uma.report.results import RunFiles, read_run

__all__ = ["draw_timeline", "timeline_figure", "TECH_COLOURS"]

TECH_COLOURS = {
    "WLAN": "#cfe8cf",
    "5G": "#cde0f5",
    "LTE": "#d8e6f7",
    "3G": "#e4ecfa",
    "EDGE": "#f6ead2",
    "GPRS": "#f8e2c8",
    "GSM": "#f6d0c8",
    "": "#eeeeee",
}
CODEC_COLOURS = {name: codec.colour for name, codec in REGISTRY.items()}
# A model codec's initialisations, as its events name them (`<codec>_init_start`, `_reinit`).
_INIT_KINDS = {f"{name}_{kind}" for name in model_names() for kind in ("init_start", "reinit")}


def _bands(ax, time_s: np.ndarray, technology: np.ndarray) -> None:
    """Shade each stretch of one technology; label it once per stretch."""
    if time_s.size == 0:
        return
    start = 0
    for i in range(1, time_s.size + 1):
        if i == time_s.size or technology[i] != technology[start]:
            end_s = time_s[i] if i < time_s.size else time_s[-1]
            tech = str(technology[start])
            ax.axvspan(time_s[start], end_s, color=TECH_COLOURS.get(tech, "#eeeeee"), lw=0)
            if end_s - time_s[start] > 0.04 * (time_s[-1] - time_s[0] + 1e-9):
                ax.text(
                    (time_s[start] + end_s) / 2, 0.97, tech or "?", transform=ax.get_xaxis_transform(),
                    ha="center", va="top", fontsize=8, color="#555555",
                )  # fmt: skip
            start = i


def _rate_kbps(time_s: np.ndarray, bits: np.ndarray, window_s: float = 1.0) -> np.ndarray:
    """Bits sent in the trailing `window_s` before each frame, as kbit/s."""
    cumulative = np.concatenate([[0.0], np.cumsum(bits)])
    first = np.searchsorted(time_s, time_s - window_s, side="right")
    return (cumulative[np.arange(1, time_s.size + 1)] - cumulative[first]) / window_s / 1000.0


def _sent(metrics: dict) -> str:
    """The kbit/s each codec the run used sent, as the title says them ("41.2 kbit/s H.264")."""
    parts = []
    for name, codec in REGISTRY.items():
        kbps = metrics.get(f"kbps_{metric_key(name)}")
        if kbps:
            parts.append(f"{kbps} kbit/s {codec.label}")
    return ", ".join(parts) or "0 kbit/s sent"


def _rates(ax, t_s: np.ndarray, f: dict) -> None:
    """Capacity, the estimate and each codec's sent rate, log scale."""
    capacity = np.maximum(np.nan_to_num(f.get("capacity_kbps", np.zeros_like(t_s))), 0.1)
    ax.step(t_s, capacity, where="post", color="#333333", lw=1.2, label="capacity")
    if "estimate_kbps" in f:
        ax.plot(t_s, f["estimate_kbps"], color="#e67e22", lw=1, label="estimate")
    codec = f.get("codec", np.array([""] * t_s.size))
    size = np.nan_to_num(f.get("size_bits", np.zeros_like(t_s)))
    for name_, colour in CODEC_COLOURS.items():
        mask = codec == name_
        if mask.any():
            rate = _rate_kbps(t_s, np.where(mask, size, 0.0))
            ax.plot(t_s, np.maximum(rate, 0.1), color=colour, lw=1, label=f"sent {name_}")
    ax.set_yscale("log")
    ax.set_ylabel("kbit/s")
    ax.legend(loc="lower left", fontsize=8, ncols=4)


def _quality(ax, shown_s: np.ndarray, f: dict) -> None:
    """Displayed and face-region PSNR at display time, the frozen instants marked below."""
    frozen = f["frozen"] > 0
    if "psnr_db" in f:
        ax.plot(shown_s, f["psnr_db"], color="#2c3e50", lw=0.8, label="displayed PSNR")
    if "psnr_face_db" in f and np.isfinite(f["psnr_face_db"]).any():
        ax.plot(shown_s, f["psnr_face_db"], color="#8e44ad", lw=0.8, label="face-region PSNR")
    ax.set_ylabel("PSNR dB")
    low = np.nanmin(f["psnr_db"]) if "psnr_db" in f and np.isfinite(f["psnr_db"]).any() else 0
    ax.scatter(
        shown_s[frozen], np.full(int(frozen.sum()), low - 1), marker="|", s=30,
        color="#c0392b", label=f"frozen ({frozen.mean():.0%})" if frozen.size else "frozen",
    )  # fmt: skip
    ax.legend(loc="lower left", fontsize=8, ncols=2)


def _rungs(rates, rungs, t_s: np.ndarray, f: dict, events) -> None:
    """The rung in use, and the run's events as lines and marks."""
    from matplotlib.ticker import MaxNLocator

    if "rung" in f:
        rungs.step(t_s, f["rung"], where="post", color="#1f5fbf", lw=1)
    styles = {
        "rung_switch": ("#1f5fbf", ":"),
        "handover": ("#555555", "--"),
        "codec_switch": ("#27ae60", "-"),
    }
    for time_ms, kind, _detail in events:
        if kind in styles:
            colour, style = styles[kind]
            width = 1.2 if kind == "codec_switch" else 0.6
            for ax in (rates, rungs) if kind == "codec_switch" else (rungs,):
                ax.axvline(time_ms / 1000.0, color=colour, ls=style, lw=width)
        elif kind == "keyframe_request":
            rungs.plot(time_ms / 1000.0, -0.5, marker="v", color="#c0392b", ms=3)
        elif kind in _INIT_KINDS:
            rungs.plot(time_ms / 1000.0, -0.5, marker="*", color="#27ae60", ms=7)
    rungs.yaxis.set_major_locator(MaxNLocator(integer=True))
    rungs.set_ylabel("rung")
    rungs.set_xlabel("time s (capture; PSNR at display)")
    rungs.set_title(
        "rung; dotted: rung switches, green: codec switches, stars: model-codec initialisations, "
        "dashed: handovers, triangles: keyframe requests",
        fontsize=8, loc="left",
    )  # fmt: skip


def _figure(run: RunFiles):
    from matplotlib.figure import Figure

    f = run.frames
    t_s = f["capture_ms"] / 1000.0
    fig = Figure(figsize=(11, 10.5), dpi=100, layout="constrained")
    rates, quality, delays, queues, rungs = fig.subplots(
        5, 1, sharex=True, height_ratios=[3, 2, 1.5, 1.2, 1.2]
    )
    name = run.metrics.get("scenario", run.folder.name)
    fig.suptitle(
        f"{name}: freeze {run.metrics.get('freeze_ratio')}, PSNR {run.metrics.get('psnr_db')} dB, "
        f"{_sent(run.metrics)}, delay p95 {run.metrics.get('delay_p95_ms')} ms",
        fontsize=10,
    )
    technology = f.get("technology", np.array([""] * t_s.size))
    for ax in (rates, quality, delays, queues, rungs):
        _bands(ax, t_s, technology)
    _rates(rates, t_s, f)
    _quality(quality, f["display_ms"] / 1000.0, f)
    _delays(delays, t_s, f, _link_bound_ms(run.folder, t_s))
    _queues(queues, t_s, f)
    _rungs(rates, rungs, t_s, f, run.events)
    rates.set_xlim(0, max(float(t_s[-1]) if t_s.size else 1.0, 1e-3))
    return fig


def _numbers(values: np.ndarray, column: str) -> np.ndarray:
    """A frames.csv column the reader kept as text, as numbers (empty: 0)."""
    from uma.errors import ConfigError

    try:
        return np.array([float(v) if v != "" else 0.0 for v in values])
    except ValueError:
        raise ConfigError(f"frames.csv ({column}): expected numbers") from None


def _link_bound_ms(folder: Path, capture_s: np.ndarray) -> np.ndarray | None:
    """The least delay the run's link allowed each frame, or None if its scenario is gone."""
    from uma.errors import UmaError

    path = folder / "scenario.yaml"
    if capture_s.size == 0 or not path.is_file():
        return None
    try:
        from uma.config import load_scenario
        from uma.metrics.link_bound import frame_delay_bounds_s
        from uma.sim.packets import HEADER_BYTES
        from uma.sim.world import scenario_link

        capacity, delay_s_of = scenario_link(load_scenario(path))
        bound_s = frame_delay_bounds_s(capacity, delay_s_of, capture_s, size_bits=8 * HEADER_BYTES)
    except (UmaError, OSError, ValueError):
        return None  # a scenario whose traces moved: the panel shows the delays alone
    return 1000.0 * bound_s


def _delays(ax, t_s: np.ndarray, f: dict, bound_ms: np.ndarray | None) -> None:
    """Each frame's delay as the metrics count it, beside the least its link allowed."""
    if "delay_ms" in f and np.isfinite(f["delay_ms"]).any():
        ax.plot(t_s, np.maximum(f["delay_ms"], 1.0), color="#2c3e50", lw=0.8, label="delay")
    if bound_ms is not None:
        ax.plot(
            t_s, np.maximum(bound_ms, 1.0), color="#27ae60", lw=0.8,
            label="least the link allowed (40-byte packets)",
        )  # fmt: skip
    ax.set_yscale("log")
    ax.set_ylabel("delay ms")
    if ax.get_lines():
        ax.legend(loc="upper left", fontsize=8, ncols=2)


def _queues(ax, t_s: np.ndarray, f: dict[str, np.ndarray]) -> None:
    """The bottleneck's queue and the engine's own, in kB, as the engine saw them per frame."""
    for column, colour, label in (
        ("queue_bytes", "#333333", "bottleneck queue"),
        ("engine_queue_bytes", "#e67e22", "engine queue (pacer)"),
    ):
        if column in f:
            kilobytes = _numbers(f[column], column) / 1000.0
            ax.step(t_s, kilobytes, where="post", color=colour, lw=1, label=label)
    ax.set_ylabel("queued kB")
    if "queue_bytes" in f or "engine_queue_bytes" in f:
        ax.legend(loc="upper left", fontsize=8, ncols=2)


def draw_timeline(results_dir: str | Path, out_png: str | Path | None = None) -> Path:
    """Draw `results_dir/timeline.png` (or `out_png`) atomically; returns its path."""
    import io

    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from uma.atomic import atomic_write_bytes

    run = read_run(results_dir)
    out = Path(out_png) if out_png is not None else run.folder / "timeline.png"
    fig = _figure(run)
    FigureCanvasAgg(fig)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    atomic_write_bytes(out, buffer.getvalue())
    return out


def timeline_figure(results_dir: str | Path):
    """The timeline of `results_dir` as a matplotlib `Figure` (not drawn to a file), for notebooks."""
    return _figure(read_run(results_dir))
