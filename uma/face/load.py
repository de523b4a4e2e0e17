"""`load_model`: a face model from uma's YAML or a Candide-3 `.wfm`, chosen by the suffix.

Above both readers, so `model` (the data type) and `wfm` (a format reader) never import each other.
A model is frozen with read-only arrays, so one read is shared by every caller until the file
changes (its size or modification time): the pure-Python YAML parse costs about 0.1 s.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

from uma.face.model import FaceModel, default_model_path, read_model_yaml

__all__ = ["load_model"]


def load_model(path: str | Path | None = None) -> FaceModel:
    """Read a face model: uma's YAML (default: the project's own wireframe) or a `.wfm` file."""
    from uma.errors import FaceError
    from uma.paths import check_regular_file

    path = Path(path) if path is not None else default_model_path()
    if path.exists() or path.is_symlink():  # a missing file: the reader names it as before
        check_regular_file(path, error=FaceError, what="face model file")
    try:
        stat = path.stat()
    except OSError:
        return _read(path)  # the reader names what is wrong with it
    # keyed by the resolved path too: the same relative name in another directory is another file
    return _read_once(path, path.resolve(), stat.st_mtime_ns, stat.st_size)


@lru_cache(maxsize=8)
def _read_once(path: Path, resolved: Path, mtime_ns: int, size: int) -> FaceModel:
    return _read(path)  # `path` as the caller gave it, for the messages


def _read(path: Path) -> FaceModel:
    if path.suffix.lower() == ".wfm":
        from uma.face.wfm import read_wfm

        return read_wfm(path)
    return read_model_yaml(path)
