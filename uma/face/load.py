"""`load_model`: a face model from uma's YAML or a Candide-3 `.wfm`, chosen by the suffix.

Above both readers, so `model` (the data type) and `wfm` (a format reader) never import each other.
"""

from __future__ import annotations

from pathlib import Path

from uma.face.model import FaceModel, default_model_path, read_model_yaml

__all__ = ["load_model"]


def load_model(path: str | Path | None = None) -> FaceModel:
    """Read a face model: uma's YAML (default: the project's own wireframe) or a `.wfm` file."""
    path = Path(path) if path is not None else default_model_path()
    if path.suffix.lower() == ".wfm":
        from uma.face.wfm import read_wfm

        return read_wfm(path)
    return read_model_yaml(path)
