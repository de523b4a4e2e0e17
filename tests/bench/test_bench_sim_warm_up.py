"""`uma bench sim` compiles or loads numba's kernels before its timed part, reports that time
apart, and names any kernel its timed part still compiled or loaded (structure, not timing)."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
from numba import njit

from uma.bench.timing import KERNEL_MODULES, kernel_signatures, kernels_loaded_since, warm_up

ROOT = Path(__file__).resolve().parents[2]

# A fresh process (no kernel loaded yet): the bench on a short run that switches to the model
# codec and scores SSIM, so the timed part calls the tracker's, the renderer's and SSIM's
# kernels; then the kernels the whole process loaded.
SCRIPT = textwrap.dedent(
    """
    import json
    from uma.bench.sim import SimBenchConfig, run_sim_bench
    from uma.bench.timing import kernel_signatures
    from uma.config.scenario import Scenario

    # Only the kernels compiled for one signature on import are there before the bench.
    early = {name for name, sigs in kernel_signatures().items() if sigs}
    assert early == {
        "uma.mbc.layered_kernels.affine_maps", "uma.mbc.layered_kernels.blend",
        "uma.mbc.layered_kernels.relight", "uma.mbc.block_kernels.block_sse",
        "uma.mbc.block_kernels.accumulate", "uma.mbc.fill_kernels.pull_level",
        "uma.mbc.fill_kernels.settle",
    }
    scenario = Scenario.model_validate({
        "name": "wlan-gsm", "seed": 1,
        "source": {"kind": "talking-head", "width": 176, "height": 144, "fps": 25},
        "route": [{"technology": "WLAN", "duration_s": 0.4},
                  {"technology": "GSM", "duration_s": 3.2}],
        "engine": {"policy": "oracle", "switching": {"policy": "threshold"}},
        "receiver": {"playout_delay_ms": 800.0},
    })
    result = run_sim_bench(SimBenchConfig(scenario=scenario, frames=90, width=176, height=144))
    loaded = sorted(name for name, sigs in kernel_signatures().items() if sigs)
    print(json.dumps({"result": result, "loaded": loaded}))
    """
)


def test_the_timed_part_compiles_and_loads_no_kernel():
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run(
        [sys.executable, "-c", SCRIPT], cwd=ROOT, env=env, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr[-2000:]
    report = json.loads(out.stdout.strip().splitlines()[-1])
    result, loaded = report["result"], report["loaded"]
    assert result["codecs"] == ["h264", "mbc"]
    # The timed run and replay used the tracker's, the renderer's and SSIM's kernels ...
    for kernel in ("uma.fit.kernels.scores", "uma.face.raster_kernels.fill_triangles",
                   "uma.mbc.layered_kernels.blend", "uma.mbc.layered_kernels.affine_maps",
                   "uma.metrics.ssim_kernel.ssim_map_inside"):  # fmt: skip
        assert kernel in loaded
    # ... all loaded by the warm-up, whose time is reported apart.
    assert result["kernels_loaded_timed"] == []
    assert result["warm_up_s"] > 0


def test_a_kernel_first_called_after_the_mark_is_named():
    module = sys.modules[__name__]
    before = kernel_signatures((module.__name__,))
    _double(np.ones(3))
    assert kernels_loaded_since(before, (module.__name__,)) == [
        f"{__name__}._double(Array(float64, 1, 'C', False, aligned=True),)"
    ]
    before = kernel_signatures((module.__name__,))
    _double(np.ones(4))  # the same types: nothing new
    assert kernels_loaded_since(before, (module.__name__,)) == []


def test_warm_up_runs_the_work_and_returns_its_seconds():
    calls = []
    seconds = warm_up(lambda: calls.append(1))
    assert calls == [1] and 0.0 <= seconds < 1.0


@njit
def _double(values):
    return values * 2.0


def test_every_module_with_kernels_is_listed():
    """A new kernel module outside `KERNEL_MODULES` would compile unseen inside a timed part."""
    package = ROOT / "uma"
    found = {
        ".".join(path.relative_to(ROOT).with_suffix("").parts)
        for path in package.rglob("*.py")
        if "from numba import" in (text := path.read_text(encoding="utf-8"))
        or "import numba" in text
    }
    assert found == set(KERNEL_MODULES)
