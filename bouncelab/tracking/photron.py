"""Photron ``.mraw`` files and their ``.cihx`` (XML) or ``.cih`` (text) headers: read
(:func:`read_mraw`) and written (:func:`write_mraw`).

An ``.mraw`` holds its frames one after the other with no header of its own: each
frame ``width x height`` pixels, top row first, 8-bit, 16-bit (little-endian words),
or 12-bit packed two pixels in three bytes, most significant bits first. The
header beside it (same name, ``.cihx`` or ``.cih``) says how:

``.cih``
    Text lines ``Key : Value``: ``Record Rate(fps)``, ``Start Frame``,
    ``Total Frame``, ``Image Width``, ``Image Height``, ``Color Type``
    (``Mono``), ``Color Bit`` (8, 12 or 16: the storage), ``EffectiveBit Depth``
    (the bits a pixel holds) and ``EffectiveBit Side`` (``Lower``: the low bits
    of a 16-bit word, ``Higher``: its high bits), ``File Format`` (``MRaw``).
``.cihx``
    The same in XML (``<cih>``, possibly after a few bytes of binary header):
    ``recordInfo/recordRate``, ``frameInfo/startFrame``, ``frameInfo/totalFrame``,
    ``imageDataInfo/resolution/width`` and ``height``,
    ``imageDataInfo/colorInfo/type`` and ``bit``, ``imageDataInfo/effectiveBit/depth``
    and ``side``, ``imageFileInfo/fileFormat``.

Photron files have no per-frame times: frame ``i`` is at ``(Start Frame + i) /
Record Rate`` seconds from the trigger.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from bouncelab.core.atomic import atomic_path
from bouncelab.core.errors import DataError
from bouncelab.core.files import read_head
from bouncelab.tracking.camera import CameraFileError, MappedFile
from bouncelab.tracking.packing import pack, packed_bytes, unpack

__all__ = ["PHOTRON_SUFFIXES", "MrawFile", "read_mraw", "write_mraw"]

PHOTRON_SUFFIXES = (".mraw", ".cihx", ".cih")
_MAX_HEADER = 16 << 20  # a header file larger than this is not a Photron header

#: Header keys read from a .cih (text) and the .cihx (XML) path of each.
_KEYS = {
    "Record Rate(fps)": "recordInfo/recordRate",
    "Start Frame": "frameInfo/startFrame",
    "Total Frame": "frameInfo/totalFrame",
    "Image Width": "imageDataInfo/resolution/width",
    "Image Height": "imageDataInfo/resolution/height",
    "Color Type": "imageDataInfo/colorInfo/type",
    "Color Bit": "imageDataInfo/colorInfo/bit",
    "EffectiveBit Depth": "imageDataInfo/effectiveBit/depth",
    "EffectiveBit Side": "imageDataInfo/effectiveBit/side",
    "File Format": "imageFileInfo/fileFormat",
    "Camera Type": "deviceInfo/deviceName",
    "Date": "fileInfo/date",
    "Time": "fileInfo/time",
    "Shutter Speed(s)": "recordInfo/shutterSpeed",
}


@dataclass(frozen=True)
class MrawFile:
    """A Photron clip: its ``.mraw`` and the header read from its ``.cihx`` or ``.cih``.

    Attributes
    ----------
    path, header_path
        The frames' file and the header's.
    width, height, frame_count
        Frame size (pixels) and frames.
    start_frame
        Number of the first frame (the trigger's frame is 0; negative before it).
    frame_rate
        ``Record Rate(fps)``, frames/s.
    storage_bits
        Bits a pixel takes in the file (8, 12 packed, 16).
    bit_depth
        Bits a pixel holds (``EffectiveBit Depth``).
    shift
        Bits to shift a 16-bit word right (``EffectiveBit Side`` ``Higher``).
    times
        Seconds from the trigger, ``(start_frame + i) / frame_rate``.
    header
        The header's fields as read (key -> text).
    """

    path: Path
    header_path: Path
    width: int
    height: int
    frame_count: int
    start_frame: int
    frame_rate: float
    storage_bits: int
    bit_depth: int
    shift: int
    times: np.ndarray
    header: dict[str, Any] = field(default_factory=dict)
    mapped: MappedFile | None = field(default=None, repr=False, compare=False)

    @property
    def frame_bytes(self) -> int:
        n = self.width * self.height
        return packed_bytes(n, 12) if self.storage_bits == 12 else n * self.storage_bits // 8

    @property
    def dtype(self) -> np.dtype:
        return np.dtype(np.uint8) if self.storage_bits == 8 else np.dtype(np.uint16)

    @property
    def levels(self) -> tuple[float, float]:
        return 0.0, float((1 << self.bit_depth) - 1)

    def frame(self, k: int) -> np.ndarray:
        """Frame ``k`` (0-based) as an (h, w) array, read through the file's memory map (its pages released
        once decoded)."""
        start = k * self.frame_bytes
        buf = self.mapped.view(start, self.frame_bytes, k)
        if self.storage_bits == 8:
            img = np.array(buf)
        elif self.storage_bits == 16:
            img = buf.view("<u2").astype(np.uint16)
            if self.shift:
                img >>= np.uint16(self.shift)
        else:
            img = unpack(buf, 12)
        del buf
        self.mapped.release(start, self.frame_bytes)
        return img.reshape(self.height, self.width)


def _header_error(message: str, path: Path, fmt: str, key: str | None = None) -> CameraFileError:
    return CameraFileError(message, file=str(path), format=fmt, field=key)


def _siblings(path: Path) -> tuple[Path, Path]:
    """(the .mraw, its header) for a path to either."""
    if path.suffix.lower() == ".mraw":
        for suffix in (".cihx", ".cih", ".CIHX", ".CIH"):
            header = path.with_suffix(suffix)
            if header.exists():
                return path, header
        raise CameraFileError(f"no header beside it: a Photron .mraw is read with its .cihx or .cih (looked for "
                              f"{path.with_suffix('.cihx').name} and {path.with_suffix('.cih').name})",
                              file=str(path), format="mraw", field="header")
    for suffix in (".mraw", ".MRAW"):
        mraw = path.with_suffix(suffix)
        if mraw.exists():
            return mraw, path
    raise CameraFileError(f"no frames beside the header: looked for {path.with_suffix('.mraw').name}", file=str(path),
                          format=path.suffix.lower().lstrip("."), field="File Format")


def _read_cih(path: Path) -> dict[str, str]:
    text = read_head(path, str(path), _MAX_HEADER).decode("utf-8", errors="replace")
    out = {}
    for line in text.splitlines():
        if " : " in line:
            key, value = line.split(" : ", 1)
            out.setdefault(key.strip(), value.strip())
    return out


def _read_cihx(path: Path) -> dict[str, str]:
    data = read_head(path, str(path), _MAX_HEADER)
    start, stop = data.find(b"<cih>"), data.rfind(b"</cih>")
    if start < 0 or stop < start:
        raise _header_error("not a Photron .cihx header: no <cih> ... </cih> element", path, "cihx")
    if b"<!ENTITY" in data[:stop]:
        raise _header_error("the header declares XML entities, which a Photron header never does", path, "cihx")
    try:
        root = ET.fromstring(data[start : stop + len(b"</cih>")])
    except ET.ParseError as exc:
        raise _header_error(f"the header's XML cannot be read: {exc}", path, "cihx") from None
    out = {}
    for key, where in _KEYS.items():
        node = root.find(where)
        if node is not None:
            # The shutter is a value element in some versions (shutterSpeed/value); others hold the text.
            value = node.findtext("value") if node.find("value") is not None else node.text
            if value is not None:
                out[key] = value.strip()
    return out


def _integer(fields: dict[str, str], key: str, path: Path, fmt: str, *, low: int | None = None,
             high: int | None = None) -> int:
    text = fields.get(key)
    if text is None:
        raise _header_error(f"the header has no {key!r}", path, fmt, key)
    try:
        value = int(float(text)) if re.fullmatch(r"\s*[-+]?\d+(\.0*)?\s*", text) else None
    except ValueError:
        value = None
    if value is None:
        raise _header_error(f"the header's {key!r} is not a whole number: {text!r}", path, fmt, key)
    if (low is not None and value < low) or (high is not None and value > high):
        raise _header_error(f"the header's {key!r} is {value}, outside {low} to {high}", path, fmt, key)
    return value


def read_mraw(path: str | Path, *, name: str | None = None) -> MrawFile:
    """A Photron clip's header (from its ``.cihx`` or ``.cih``) and frames' file (``.mraw``).

    Parameters
    ----------
    path
        The ``.mraw`` (its header is found beside it, same name) or the header.
    name
        How to name the ``.mraw`` in errors (default: its path).

    Raises
    ------
    CameraFileError
        A missing header or ``.mraw``, a header that lacks a field or holds a
        bad value (named), colour frames, or an ``.mraw`` shorter than the
        frames its header declares.
    """
    mraw, hdr = _siblings(Path(path))
    fmt = hdr.suffix.lower().lstrip(".")
    try:
        fields = _read_cihx(hdr) if fmt == "cihx" else _read_cih(hdr)
    except OSError as exc:
        raise _header_error(f"cannot read the header: {exc.strerror or exc}", hdr, fmt) from None
    if not fields:
        raise _header_error("not a Photron header: no 'Key : Value' lines", hdr, fmt)
    file_format = fields.get("File Format", "MRaw")
    if file_format.lower() not in ("mraw", "raw"):
        raise _header_error(f"the header describes {file_format!r} files, not MRaw", hdr, fmt, "File Format")
    if fields.get("Color Type", "Mono").lower() not in ("mono", "monochrome"):
        raise _header_error(f"colour frames ({fields['Color Type']!r}); bouncelab reads monochrome .mraw", hdr, fmt,
                            "Color Type")
    width = _integer(fields, "Image Width", hdr, fmt, low=1, high=1 << 16)
    height = _integer(fields, "Image Height", hdr, fmt, low=1, high=1 << 16)
    count = _integer(fields, "Total Frame", hdr, fmt, low=1, high=1 << 26)
    start = _integer(fields, "Start Frame", hdr, fmt, low=-(1 << 31), high=(1 << 31) - 1)
    bits = _integer(fields, "Color Bit", hdr, fmt)
    if bits not in (8, 12, 16):
        raise _header_error(f"{bits} bits a pixel (Color Bit 8, 12 or 16)", hdr, fmt, "Color Bit")
    depth = _integer(fields, "EffectiveBit Depth", hdr, fmt, low=1, high=bits) \
        if "EffectiveBit Depth" in fields else bits
    side = fields.get("EffectiveBit Side", "Lower").lower()
    if side not in ("lower", "higher"):
        raise _header_error(f"EffectiveBit Side {fields['EffectiveBit Side']!r} (Lower or Higher)", hdr, fmt,
                            "EffectiveBit Side")
    shift = bits - depth if side == "higher" and bits == 16 else 0
    text = fields.get("Record Rate(fps)")
    try:
        rate = float(text) if text is not None else float("nan")
    except ValueError:
        rate = float("nan")
    if not (np.isfinite(rate) and 0 < rate < 1e9):
        raise _header_error(f"the header's 'Record Rate(fps)' is not a frame rate: {text!r}", hdr, fmt,
                            "Record Rate(fps)")
    if bits == 12 and (width * height) % 2:
        raise _header_error(f"{width} x {height} pixels cannot be packed two in three bytes", hdr, fmt, "Image Width")
    label = name or str(mraw)
    clip = MrawFile(path=mraw, header_path=hdr, width=width, height=height, frame_count=count, start_frame=start,
                    frame_rate=rate, storage_bits=bits, bit_depth=depth, shift=shift,
                    times=(start + np.arange(count)) / rate, header=fields,
                    mapped=MappedFile(mraw, label, "mraw"))
    try:
        size = mraw.stat().st_size
    except OSError as exc:
        raise CameraFileError(f"cannot read the frames' file: {exc.strerror or exc}", file=label,
                              format="mraw") from None
    need = count * clip.frame_bytes
    if size < need:
        raise CameraFileError(f"the file holds {size:,} bytes; its header declares {count} frames of {width} x "
                              f"{height} pixels at {bits} bits, {need:,} bytes (truncated, or the wrong header)",
                              file=label, format="mraw", frame=size // clip.frame_bytes)
    return clip


def write_mraw(
    path: str | Path,
    frames: np.ndarray,
    *,
    fps: float,
    bit_depth: int | None = None,
    storage_bits: int | None = None,
    start_frame: int = 0,
    header: str = "cihx",
    side: str = "Lower",
) -> Path:
    """Write grey frames as a Photron ``.mraw`` and its header (``.cihx`` or ``.cih``), atomically.

    Parameters
    ----------
    path
        The ``.mraw`` to write; the header goes beside it.
    frames
        (t, h, w) uint8 or uint16 frames.
    fps
        Record rate, frames/s.
    bit_depth
        ``EffectiveBit Depth`` (default 8 for uint8 frames, else the storage's bits).
    storage_bits
        ``Color Bit``: 8, 12 (packed) or 16 (default 8 for uint8 frames, else 16).
    start_frame
        ``Start Frame`` (negative: frames before the trigger).
    header
        ``"cihx"`` (XML) or ``"cih"`` (text).
    side
        ``EffectiveBit Side`` of 16-bit words: ``"Lower"`` or ``"Higher"``.
    """
    arr = np.asarray(frames)
    if arr.ndim != 3 or arr.dtype not in (np.uint8, np.uint16):
        raise DataError(f"frames must be a (t, h, w) uint8 or uint16 array; got {arr.dtype} {arr.shape}",
                        option="frames")
    n, h, w = arr.shape
    storage = storage_bits or (8 if arr.dtype == np.uint8 else 16)
    depth = bit_depth or (8 if arr.dtype == np.uint8 else storage)
    if storage not in (8, 12, 16) or depth > storage or (storage == 8) != (arr.dtype == np.uint8):
        raise DataError(f"storage_bits {storage} (8 for uint8 frames, 12 or 16 for uint16) and bit_depth {depth} "
                        "(at most the storage's)", option="storage_bits")
    if header not in ("cihx", "cih") or side not in ("Lower", "Higher"):
        raise DataError(f"header must be 'cihx' or 'cih' and side 'Lower' or 'Higher'; got {header!r}, {side!r}",
                        option="header")
    if int(arr.max(initial=0)) >= 1 << depth:
        raise DataError(f"frames hold values up to {int(arr.max())}, more than {depth} bits", option="bit_depth")
    mraw = Path(path)
    shift = storage - depth if side == "Higher" and storage == 16 else 0
    with atomic_path(mraw) as tmp, open(tmp, "wb") as fh:
        for k in range(n):
            img = arr[k]
            if storage == 12:
                fh.write(pack(img, 12).tobytes())
            elif storage == 16:
                fh.write((img.astype(np.uint16) << np.uint16(shift)).astype("<u2").tobytes())
            else:
                fh.write(np.ascontiguousarray(img).tobytes())
    values = {"Date": "2024/05/01", "Time": "12:00", "Camera Type": "written by bouncelab.tracking.write_mraw",
              "Record Rate(fps)": f"{fps:g}", "Shutter Speed(s)": f"1/{round(fps * 1.1)}", "Total Frame": str(n),
              "Original Total Frame": str(n), "Start Frame": str(start_frame), "Image Width": str(w),
              "Image Height": str(h), "Color Type": "Mono", "Color Bit": str(storage),
              "File Format": "MRaw", "EffectiveBit Depth": str(depth), "EffectiveBit Side": side}
    if header == "cih":
        text = "#Camera Information Header\n" + "".join(f"{k} : {v}\n" for k, v in values.items())
        data = text.encode()
    else:
        data = _cihx(values)
    with atomic_path(mraw.with_suffix("." + header)) as tmp, open(tmp, "wb") as fh:
        fh.write(data)
    return mraw


def _cihx(values: dict[str, str]) -> bytes:
    """The XML of a .cihx, behind the few bytes of binary header that Photron's files carry."""
    root = ET.Element("cih")
    for key, where in _KEYS.items():
        if key not in values:
            continue
        node = root
        for part in where.split("/"):
            child = node.find(part)
            node = child if child is not None else ET.SubElement(node, part)
        node.text = values[key]
    xml = ET.tostring(root, encoding="unicode")
    return b"\x00\x00\x00\x00" + b'<?xml version="1.0" encoding="UTF-8" ?>\n' + xml.encode()
