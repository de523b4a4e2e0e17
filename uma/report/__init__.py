"""Reports to look at: the timeline PNG of a run, the receiver-view video, the sweep summary plot.

matplotlib and PyAV are imported inside the functions that draw or encode.
"""

from uma.report.results import RunFiles, read_run
from uma.report.sweep_plot import draw_sweep_summary
from uma.report.timeline import draw_timeline
from uma.report.video import write_receiver_video

__all__ = ["RunFiles", "read_run", "draw_timeline", "draw_sweep_summary", "write_receiver_video"]
