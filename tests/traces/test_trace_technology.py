import numpy as np
import pytest

from uma.errors import TraceError
from uma.paths import traces_dir
from uma.traces import (
    LABELS,
    TECHNOLOGIES,
    RateModel,
    generate,
    normalise_technology,
    read_trace,
    technology_defaults,
)
from uma.traces.project_traces import PROJECT_TRACES, build_project_trace, main


def test_every_label_has_defaults():
    assert set(TECHNOLOGIES) == set(LABELS)
    for name, tech in TECHNOLOGIES.items():
        assert tech.name == name
        assert 0 < tech.delay_ms < 1000 and 0 <= tech.loss_rate < 0.02


def test_slower_radios_are_slower_and_later():
    order = ["GSM", "GPRS", "EDGE", "3G", "LTE", "5G"]
    means = [TECHNOLOGIES[name].rate.mean_kbps for name in order]
    assert means == sorted(means)
    assert (
        TECHNOLOGIES["GPRS"].delay_ms > TECHNOLOGIES["EDGE"].delay_ms > TECHNOLOGIES["3G"].delay_ms
    )
    assert (
        TECHNOLOGIES["3G"].delay_ms > TECHNOLOGIES["LTE"].delay_ms > TECHNOLOGIES["WLAN"].delay_ms
    )


@pytest.mark.parametrize(
    "name, label",
    [("HSPA+", "3G"), ("hsdpa", "3G"), ("UMTS", "3G"), ("HSUPA", "3G"), ("WiFi", "WLAN"),
     ("GPRS", "GPRS"), ("EDGE", "EDGE"), ("NR", "5G"), ("-", ""), ("", "")],
)  # fmt: skip
def test_normalise(name, label):
    assert normalise_technology(name) == label
    assert technology_defaults(name).name == label


def test_unknown_defaults_are_neutral_and_typos_are_errors():
    assert technology_defaults("").delay_ms == 50.0 and technology_defaults("").loss_rate == 0.0
    with pytest.raises(TraceError, match="got 'GRPS'"):
        technology_defaults("GRPS")


@pytest.mark.parametrize(
    "tech, low, high",
    [("GSM", 4, 10), ("GPRS", 15, 60), ("EDGE", 80, 240), ("3G", 300, 2000), ("LTE", 3000, 50000),
     ("WLAN", 1500, 20000)],
)  # fmt: skip
def test_generated_rates_sit_in_the_technology_range(tech, low, high):
    trace = generate(tech, 1800, rng=1)
    model = TECHNOLOGIES[tech].rate
    nonzero = trace.rates_kbps[trace.rates_kbps > 0]
    assert low <= np.median(nonzero) <= high
    assert nonzero.min() >= model.min_kbps and nonzero.max() <= model.max_kbps
    assert set(trace.technologies) == {tech}


def test_generated_rates_fade_and_stay_correlated():
    trace = generate("GPRS", 3600, rng=5)
    zero = trace.rates_kbps == 0
    assert 0.005 < zero.mean() < 0.1  # about one 1-3 s outage a minute
    logs = np.log(trace.rates_kbps[~zero])
    lag1 = np.corrcoef(logs[:-1], logs[1:])[0, 1]
    assert 0.6 < lag1 < 0.95  # AR(1) with 0.85 per second, blurred by clipping and gaps


def test_generate_is_reproducible_and_sized():
    a = generate("3G", 10.5, rng=np.random.default_rng(3), step_s=0.5)
    assert a == generate("3G", 10.5, rng=3, step_s=0.5)
    assert a != generate("3G", 10.5, rng=4, step_s=0.5)
    assert len(a) == 21 and a.duration_s == 10.5 and a.times_s[1] == 0.5
    short = generate("EDGE", 2.2, rng=0)
    assert len(short) == 3 and short.widths_s[-1] == pytest.approx(0.2)


def test_generate_errors():
    with pytest.raises(TraceError, match="cannot generate rates for technology 'Carrier pigeon'"):
        generate("Carrier pigeon", 10, rng=0)
    with pytest.raises(TraceError, match="cannot generate rates for technology ''"):
        generate("", 10, rng=0)
    with pytest.raises(TraceError, match="expected positive durations"):
        generate("3G", 0, rng=0)
    with pytest.raises(TraceError, match="at most 10,000,000 steps"):
        generate("3G", 1e12, rng=0)
    with pytest.raises(TraceError, match="sigma_log"):
        RateModel(10.0, 1.0, 20.0, -0.1, 0.5)
    with pytest.raises(TraceError, match="min_kbps"):
        RateModel(10.0, 11.0, 20.0, 0.1, 0.5)


def _same_trace(a, b) -> bool:
    # numpy's elementary functions may differ in the last bit between releases (numpy is not
    # pinned), so generated rates are compared to 1e-12 relative; everything else exactly.
    return (
        np.array_equal(a.times_s, b.times_s)
        and np.allclose(a.rates_kbps, b.rates_kbps, rtol=1e-12, atol=0)
        and a.technologies == b.technologies
        and a.duration_s == b.duration_s
    )


def test_project_traces_are_what_the_documented_command_writes(tmp_path):
    for spec in PROJECT_TRACES:
        committed = read_trace(traces_dir() / spec.name)
        assert _same_trace(committed, build_project_trace(spec)), spec.name
        assert committed.duration_s == pytest.approx(sum(s.duration_s for s in spec.segments))
    assert main([str(tmp_path)]) == 0
    for spec in PROJECT_TRACES:
        written = read_trace(tmp_path / spec.name)
        assert _same_trace(written, read_trace(traces_dir() / spec.name)), spec.name


def test_project_gprs_outage_has_its_outage():
    trace = read_trace(traces_dir() / "gprs-outage.csv")
    assert trace.rate_kbps_at(45.0) == 0.0 and trace.technology_at(45.0) == "GPRS"
    assert {"EDGE", "GPRS", "GSM"} == set(trace.technologies)
