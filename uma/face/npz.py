"""Deflated `.npz` archives of plain arrays, written reproducibly and read defensively.

Content descriptions travel as such archives. The reader trusts nothing in the file: it reads
it whole (up to a stated size), checks the zip structure and every member's checksum, parses
each `.npy` header itself and refuses object arrays, so truncated, bit-flipped or foreign bytes
end in one `FaceError` naming the file and the member, never a zip, zlib or pickle message.
"""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np

from uma.errors import FaceError
from uma.face.image_bytes import what_the_bytes_look_like
from uma.paths import read_capped

__all__ = ["write_npz", "read_npz", "MAX_ARCHIVE_BYTES"]

# Far above any description (about 12 kB for a CIF face); also caps what a member may claim to
# hold once inflated, so a crafted archive cannot make the reader allocate gigabytes.
MAX_ARCHIVE_BYTES = 64 * 1024 * 1024


def write_npz(**arrays: np.ndarray) -> bytes:
    """A deflated .npz that `np.load` reads, byte-identical for identical arrays (np.savez
    stamps each member with the current time)."""
    import zipfile

    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, array in arrays.items():
            member = io.BytesIO()
            np.lib.format.write_array(member, np.asarray(array), allow_pickle=False)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            archive.writestr(info, member.getvalue())
    return buffer.getvalue()


def read_npz(path: str | Path, *, what: str, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The arrays `names` of the archive at `path` (a `what`, for messages), read-only.

    Every failure is a `FaceError` of one line: `PATH: expected WHAT (...), got ...`, naming the
    member when one is at fault. Extra members are ignored.
    """
    import zipfile
    import zlib

    path = Path(path)
    data = read_capped(path, max_bytes=MAX_ARCHIVE_BYTES, error=FaceError, what=what)
    expected = f"expected {what} (a zip of .npy arrays)"
    if not data.startswith(b"PK\x03\x04"):
        raise FaceError(f"{path}: {expected}, got {what_the_bytes_look_like(data)}")
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
    except (zipfile.BadZipFile, ValueError, OSError, EOFError, NotImplementedError) as err:
        raise FaceError(f"{path}: {expected}, got a damaged or truncated zip ({err})") from None
    with archive:
        members = {info.filename: info for info in archive.infolist()}
        out = {}
        for name in names:
            info = members.get(f"{name}.npy")
            if info is None:
                raise FaceError(f"{path}: {expected}, got an archive without {name}.npy")
            if info.file_size > MAX_ARCHIVE_BYTES:
                raise FaceError(
                    f"{path}: {name}: expected at most {MAX_ARCHIVE_BYTES} bytes, "
                    f"the archive says {info.file_size}"
                )
            try:
                raw = archive.read(info)
            except (zipfile.BadZipFile, zlib.error, ValueError, OSError, EOFError) as err:
                raise FaceError(
                    f"{path}: {name}: expected an intact member, got a damaged or truncated one "
                    f"({err})"
                ) from None
            except NotImplementedError as err:
                raise FaceError(
                    f"{path}: {name}: expected deflate or no compression, got another ({err})"
                ) from None
            out[name] = _parse_npy(raw, f"{path}: {name}")
    return out


def _parse_npy(raw: bytes, where: str) -> np.ndarray:
    """One `.npy` member, without `np.load`: header checked, no objects, size matching."""
    stream = io.BytesIO(raw)
    try:
        version = np.lib.format.read_magic(stream)
        if version == (1, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_1_0(stream)
        elif version in ((2, 0), (3, 0)):
            shape, fortran, dtype = np.lib.format.read_array_header_2_0(stream)
        else:
            raise ValueError(f"version {version}")
    except (ValueError, SyntaxError, TypeError, EOFError, UnicodeDecodeError) as err:
        raise FaceError(f"{where}: expected a .npy array, got a bad header ({err})") from None
    if dtype.hasobject or dtype.kind not in "biuf" or dtype.itemsize == 0:
        raise FaceError(f"{where}: expected numbers, got dtype {dtype}")
    if any(d < 0 for d in shape):
        raise FaceError(f"{where}: expected a shape of sizes >= 0, got {shape}")
    count = math.prod(shape)
    body = raw[stream.tell() :]
    if count * dtype.itemsize != len(body):
        raise FaceError(
            f"{where}: expected {count * dtype.itemsize} bytes for shape {shape} {dtype}, "
            f"got {len(body)}"
        )
    array = np.frombuffer(body, dtype=dtype).reshape(shape, order="F" if fortran else "C")
    return array
