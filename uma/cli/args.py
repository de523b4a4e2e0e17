"""Argument types shared by the sub-commands (standard library only)."""

from __future__ import annotations

import argparse
import re
from typing import NoReturn

__all__ = [
    "frame_size", "seed", "workers", "seconds", "setting", "setting_value", "one_executor",
    "OneLineParser", "one_line",
]  # fmt: skip

MAX_SEED = 2**63 - 1  # the scenario's own bound on `seed` (uma.config.scenario)
MAX_WORKERS = 64  # local processes; a cluster (--scheduler) brings its own
MAX_SECONDS = 3600.0

_REWORDED = (
    (re.compile(r"^argument (\S+): invalid int value: (.*)$"), r"\1: expected an integer, got \2"),
    (re.compile(r"^argument (\S+): invalid float value: (.*)$"), r"\1: expected a number, got \2"),
    (re.compile(r"^argument (\S+): invalid choice: (.*) \(choose from (.*)\)$"), None),
    (re.compile(r"^argument (\S+): (.*)$"), r"\1: \2"),
)


def one_line(message: str, prog: str) -> str:
    """argparse's `message` as uma words errors: `OPTION: expected ..., got ...`, then where
    to read more. `argument --frames: invalid int value: 'ten'` becomes
    `--frames: expected an integer, got 'ten' (uma bench codec --help)`."""
    message = " ".join(message.split())
    for pattern, replacement in _REWORDED:
        found = pattern.match(message)
        if found is None:
            continue
        if replacement is None:
            choices = ", ".join(c.strip("'") for c in found.group(3).split(", "))
            message = f"{found.group(1)}: expected one of {choices}, got {found.group(2)}"
        else:
            message = found.expand(replacement)
        break
    return f"{message} ({prog} --help)"


class OneLineParser(argparse.ArgumentParser):
    """An `ArgumentParser` whose errors are a `ConfigError`, which `uma.cli.main` prints as
    one line, `uma: error: ...`, and exit 2, as every other bad input gets, rather than the
    usage block and the error. Sub-parsers added with `add_subparsers` are of this class too."""

    def error(self, message: str) -> NoReturn:
        from uma.errors import ConfigError

        raise ConfigError(one_line(message, self.prog))


NAMED_SIZES = {"cif": (352, 288), "qcif": (176, 144)}


def setting(text: str) -> tuple[str, str]:
    """`KEY=VALUE` (`engine.mbc.refresh.enabled=true`) as (key path, value text); the value is
    read as YAML and the key checked against the scenario by the command that takes it."""
    key, equals, value = text.partition("=")
    if not equals or not key.strip():
        raise argparse.ArgumentTypeError(
            f"expected KEY=VALUE such as engine.mbc.refresh.enabled=true, got {text!r}"
        )
    return key.strip(), value


def setting_value(key: str, text: str):
    """A `setting`'s value text read as YAML (bounded as a scenario file is); bad YAML is a
    `ConfigError` naming `--set KEY`."""
    from uma.config.yamlfile import parse_yaml_bounded

    return parse_yaml_bounded(text, f"--set {key}")[0]


def frame_size(text: str) -> tuple[int, int]:
    """`cif`, `qcif` or `WxH` with even sides of at least 16 pixels."""
    if text.lower() in NAMED_SIZES:
        return NAMED_SIZES[text.lower()]
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected cif, qcif or WxH, got {text!r}") from None
    if width < 16 or height < 16 or width % 2 or height % 2:
        raise argparse.ArgumentTypeError(f"expected even sides of at least 16 pixels, got {text!r}")
    return width, height


def _integer(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None


def seed(text: str) -> int:
    """A random seed: an integer from 0 to 2**63 - 1, as a scenario's `seed` may be."""
    value = _integer(text)
    if not 0 <= value <= MAX_SEED:
        raise argparse.ArgumentTypeError(f"expected an integer from 0 to 2**63 - 1, got {text!r}")
    return value


def workers(text: str) -> int:
    """A count of local worker processes, 1 to `MAX_WORKERS` (each holds a whole run)."""
    value = _integer(text)
    if not 1 <= value <= MAX_WORKERS:
        raise argparse.ArgumentTypeError(
            f"expected 1 to {MAX_WORKERS} worker processes, got {text!r}"
        )
    return value


def seconds(text: str) -> float:
    """A positive duration in seconds, at most an hour."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of seconds, got {text!r}") from None
    if not 0 < value <= MAX_SECONDS:
        raise argparse.ArgumentTypeError(
            f"expected a number of seconds above 0 and at most {MAX_SECONDS:g}, got {text!r}"
        )
    return value


def one_executor(args: argparse.Namespace) -> None:
    """Refuse `--workers` beside `--scheduler` (a cluster has its own workers)."""
    from uma.errors import ConfigError

    if args.workers is not None and args.scheduler:
        raise ConfigError("--workers and --scheduler: give one (a cluster has its own workers)")
