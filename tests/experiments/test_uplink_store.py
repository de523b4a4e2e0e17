"""The on-disk store of sender streams: a run through it is byte for byte the run computed afresh,
cold or warm, in any process; writes are atomic, a damaged file is a miss, the size is bounded."""

import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from uma.config.scenario import Scenario
from uma.errors import ConfigError, OutputError
from uma.experiments.uplink_store import (
    DEFAULT_MB,
    FOLDER,
    StoreSettings,
    UplinkStore,
    evict,
    open_store,
    store_settings,
)
from uma.sim import run_scenario
from uma.sim.summary import run_metrics


def _scenario(duration_s: float) -> Scenario:
    return Scenario.model_validate(
        {
            "name": "store",
            "seed": 5,
            "source": {"kind": "talking-head", "width": 176, "height": 144, "fps": 25},
            "route": [{"technology": "3G", "duration_s": 4.0}],
            "duration_s": duration_s,
            "sender": {"rate_kbps": 600.0},
            "metrics": {"ssim": False, "workers": 0},
        }
    )


def _files(result) -> tuple[str, str, dict]:
    events = "\n".join(f"{e.time_s!r} {e.kind} {e.detail}" for e in result.events)
    return result.log.to_csv(), events, run_metrics(result)


@pytest.fixture(scope="module")
def fresh():
    return {d: _files(run_scenario(_scenario(d))) for d in (0.8, 1.2)}


def _settings(tmp_path: Path, max_bytes: int = 2**30) -> StoreSettings:
    return StoreSettings(tmp_path / FOLDER, max_bytes)


def _stored(settings: StoreSettings) -> list[Path]:
    return sorted(settings.root.rglob("*.bin"))


def test_a_run_through_the_store_cold_then_warm_is_the_run_computed_afresh(tmp_path, fresh):
    settings = _settings(tmp_path)
    cold = UplinkStore(settings)  # each store object stands for another process
    assert _files(run_scenario(_scenario(0.8), uplink=cold)) == fresh[0.8]
    assert cold.hits == 0 and cold.written == 20 and len(_stored(settings)) == 20
    warm = UplinkStore(settings)
    assert _files(run_scenario(_scenario(0.8), uplink=warm)) == fresh[0.8]
    assert warm.hits == 20 and warm.written == 0
    assert not warm.pictures and not warm.frames  # each picture handed out once, none kept


def test_a_longer_run_catches_up_where_the_store_ends(tmp_path, fresh):
    settings = _settings(tmp_path)
    run_scenario(_scenario(0.8), uplink=UplinkStore(settings))
    longer = UplinkStore(settings)
    assert _files(run_scenario(_scenario(1.2), uplink=longer)) == fresh[1.2]
    assert longer.hits == 20 and longer.written == 10 and len(_stored(settings)) == 30


def test_damaged_or_foreign_files_are_misses_and_the_run_is_unchanged(tmp_path, fresh):
    settings = _settings(tmp_path)
    run_scenario(_scenario(0.8), uplink=UplinkStore(settings))
    files = _stored(settings)
    files[5].write_bytes(files[5].read_bytes()[:-1])  # cut short
    files[9].write_bytes(b"not a frame")
    (files[0].parent / ".half-written.tmp").write_bytes(b"\0" * 100)  # a writer killed mid-way
    store = UplinkStore(settings)
    assert _files(run_scenario(_scenario(0.8), uplink=store)) == fresh[0.8]
    assert store.misses == 1 and store.hits < 20  # the frames before the first damaged one
    again = UplinkStore(settings)  # the damaged files were removed and written again
    assert _files(run_scenario(_scenario(0.8), uplink=again)) == fresh[0.8]
    assert again.hits == 20


def test_two_writers_of_one_stream_leave_whole_files(tmp_path, fresh):
    settings = _settings(tmp_path)
    first, second = UplinkStore(settings), UplinkStore(settings)
    run_scenario(_scenario(0.8), uplink=first)
    run_scenario(_scenario(0.8), uplink=second)
    both = UplinkStore(settings)
    assert _files(run_scenario(_scenario(0.8), uplink=both)) == fresh[0.8]
    assert both.hits == 20 and not list(settings.root.rglob("*.tmp"))


def test_in_memory_a_run_and_its_replay_share_one_read(tmp_path, fresh):
    settings = _settings(tmp_path)
    run_scenario(_scenario(0.8), uplink=UplinkStore(settings))
    store = UplinkStore(settings, in_memory=True)
    for _ in range(2):
        assert _files(run_scenario(_scenario(0.8), uplink=store)) == fresh[0.8]
    assert store.hits == 40 and len(store.pictures) == 20


def test_a_picture_is_read_back_as_written(tmp_path):
    from uma.sim.uplink import UplinkFrame

    store = UplinkStore(_settings(tmp_path))
    picture = np.random.default_rng(1).integers(0, 256, (216, 176), dtype=np.uint8)
    for key, shown in ((b"a" * 20, picture), (b"b" * 20, None)):
        store.keep(UplinkFrame(b"\x00\x01coded", 7, True, key))
        store.keep_picture(key, shown)
        found = UplinkStore(_settings(tmp_path)).found(key)
        assert found == UplinkFrame(b"\x00\x01coded", 7, True, key)
    reader = UplinkStore(_settings(tmp_path))
    assert reader.found(b"a" * 20) is not None
    back = reader.pictures[b"a" * 20]
    assert np.array_equal(back, picture) and back.flags.writeable


def test_the_store_stays_within_its_bound_evicting_the_oldest(tmp_path):
    settings = _settings(tmp_path, max_bytes=10 * 40_000)
    run_scenario(_scenario(0.8), uplink=UplinkStore(settings))  # 20 frames of ~38 kB
    sizes = [p.stat().st_size for p in _stored(settings)]
    assert sum(sizes) <= settings.max_bytes and len(sizes) < 20
    root = tmp_path / "lru"
    for k, age in enumerate((30, 10, 20)):
        (root / "ab").mkdir(parents=True, exist_ok=True)
        path = root / "ab" / f"{k}.bin"
        path.write_bytes(b"x" * 100)
        os.utime(path, (1e9 + age, 1e9 + age))
    assert evict(root, 150) == 100
    assert [p.name for p in sorted(root.rglob("*.bin"))] == ["0.bin"]  # the newest stays


def test_a_store_that_cannot_write_stops_writing_and_the_run_goes_on(tmp_path, fresh):
    blocker = tmp_path / "file"
    blocker.write_text("in the way")
    store = UplinkStore(StoreSettings(blocker / FOLDER, 2**30))
    assert _files(run_scenario(_scenario(0.8), uplink=store)) == fresh[0.8]
    assert store.written == 0


def test_settings_from_the_environment(tmp_path):
    assert store_settings({"UMA_CACHE": "off"}) is None
    assert store_settings({"UMA_CACHE": " OFF "}) is None
    chosen = store_settings({"UMA_CACHE": str(tmp_path), "UMA_CACHE_MB": "2"})
    assert chosen == StoreSettings(tmp_path / FOLDER, 2 * 2**20)
    default = store_settings({"XDG_CACHE_HOME": str(tmp_path)})
    assert default == StoreSettings(tmp_path / "uma" / FOLDER, DEFAULT_MB * 2**20)
    assert open_store(None) is None and open_store(chosen.task()).settings == chosen


@given(st.text(max_size=12))
def test_a_bad_size_is_one_error_naming_the_variable(text):
    try:
        settings = store_settings({"UMA_CACHE": "/nowhere", "UMA_CACHE_MB": text})
    except ConfigError as err:
        assert "UMA_CACHE_MB" in str(err) and repr(text.strip()) in str(err)
    else:
        assert settings is not None and settings.max_bytes >= 2**20


def test_a_sweep_refuses_a_store_inside_its_folder(tmp_path):
    from uma.experiments.sweep import run_sweep

    out = tmp_path / "sweep"
    with pytest.raises(OutputError, match="UMA_CACHE"):
        run_sweep(None, out, None, uplink=StoreSettings(out / "cache" / FOLDER, 2**30))
