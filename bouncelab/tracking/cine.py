"""Phantom ``.cine`` files: the header read (:func:`read_cine`), frames read by memory map, and files
written (:func:`write_cine`), from the documented layout.

Layout (all little-endian)
--------------------------
* ``CINEFILEHEADER`` (44 bytes at 0): ``Type`` ``"CI"``, ``Headersize`` (44),
  ``Compression`` (0: grey; 1: JPEG; 2: uninterpolated), ``Version`` (1: 64-bit
  image offsets), ``FirstMovieImage``, ``TotalImageCount``, ``FirstImageNo``
  (int32; negative for frames before the trigger), ``ImageCount``,
  ``OffImageHeader``, ``OffSetup``, ``OffImageOffsets`` (uint32 offsets), and
  ``TriggerTime`` (a ``TIME64``: uint32 fraction of a second in units of 2^-32 s,
  then uint32 seconds since 1970, UTC).
* ``BITMAPINFOHEADER`` (40 bytes at ``OffImageHeader``): ``biWidth``,
  ``biHeight`` (negative: rows stored top-down), ``biBitCount`` (8 or 16 for
  grey; 24 and 48 are colour), ``biCompression`` (0: one pixel a byte or a 16-bit word;
  256: 10-bit packed; 1024: 12-bit packed), ``biSizeImage``.
* ``SETUP`` (at ``OffSetup``; its ``Length`` at byte 142, after the mark
  ``"ST"``): ``FrameRate16`` (uint16 at 0), ``FrameRate`` (uint32 at 768),
  ``CFA`` (808; 0 is a grey sensor), ``RealBPP`` (uint32 at 896: the bits a
  pixel holds, 8 to 16), ``Decimation`` (uint32 at 1556; 0 in old files means
  none), ``ShutterNs`` (1568), ``BlackLevel``/``WhiteLevel`` (int32 at 5732 and
  5736) and ``dFrameRate`` (a double at 10400), each read only when ``Length``
  covers it.
* Tagged blocks from ``OffSetup + Length`` to ``OffImageOffsets``: ``BlockSize``
  (uint32, the block's bytes), ``Type`` (uint16), ``Reserved`` (uint16), data.
  Type 1002 holds one ``TIME64`` per image (its time), 1003 one uint32 exposure
  per image (2^-32 s).
* ``ImageCount`` int64 image offsets at ``OffImageOffsets``; at each, an
  annotation (``AnnotationSize`` uint32 counting itself, the annotation bytes,
  and the image's size in bytes as the last uint32) and the pixels.

Pixels: 8-bit; 16-bit little-endian words holding ``RealBPP`` bits (12, 14 or
16) in their low bits; 10- or 12-bit packed, most significant bits first
(:mod:`bouncelab.tracking.packing`). Rows of 8- and 16-bit images are stored
bottom-up (the first row in the file is the bottom of the picture) unless
``biHeight`` is negative; packed images are read top-down, as ``pims`` and
FFmpeg read them. Colour, JPEG-compressed and raw colour (Bayer) files are refused
(the tracker works on grey frames: save the clip grey in the camera software).

Times. A file with a 1002 block gives each frame its own time, so frames the
camera dropped show as a gap; without it, image ``i`` is at ``(FirstImageNo +
i * Decimation) / rate``. Times are seconds from the trigger.
"""

from __future__ import annotations

import datetime as _dt
import os
import struct
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from bouncelab.core.atomic import atomic_path
from bouncelab.core.errors import DataError
from bouncelab.core.files import check_regular_file
from bouncelab.tracking.camera import CameraFileError, MappedFile, frame_gaps
from bouncelab.tracking.packing import pack, packed_bytes, unpack

__all__ = ["CINE_SUFFIXES", "CineFile", "read_cine", "write_cine"]

CINE_SUFFIXES = (".cine",)

_HEADER = struct.Struct("<2sHHHiIiIIIIQ")  # CINEFILEHEADER, 44 bytes
_BITMAP = struct.Struct("<IiiHHIIiiII")  # BITMAPINFOHEADER, 40 bytes
_FRACTION = 2.0**32
#: SETUP fields read: name -> (offset in SETUP, struct format).
_SETUP = {
    "FrameRate16": (0, "<H"),
    "Length": (142, "<H"),
    "ImWidth": (737, "<H"),
    "ImHeight": (739, "<H"),
    "Serial": (743, "<I"),
    "bFlipH": (756, "<i"),
    "bFlipV": (760, "<i"),
    "FrameRate": (768, "<I"),
    "CameraVersion": (792, "<I"),
    "SoftwareVersion": (800, "<I"),
    "CFA": (808, "<I"),
    "RealBPP": (896, "<I"),
    "Decimation": (1556, "<I"),
    "ShutterNs": (1568, "<I"),
    "BlackLevel": (5732, "<i"),
    "WhiteLevel": (5736, "<i"),
    "dFrameRate": (10400, "<d"),
}
_MAX_IMAGES = 1 << 26  # more images than any camera's memory holds: a damaged count


@dataclass(frozen=True)
class CineFile:
    """A ``.cine`` file's header, as :func:`read_cine` reads it.

    Attributes
    ----------
    path
        The file.
    width, height
        Frame size, pixels.
    image_count
        Images in the file.
    first_image_no
        Number of the first image (the trigger's image is 0; negative before it).
    bit_depth
        Bits a pixel holds (``RealBPP``; ``biBitCount`` for old files).
    storage
        ``"8"`` (a byte a pixel), ``"16"`` (16-bit words), ``"10p"``/``"12p"``
        (packed).
    bottom_up
        Whether the first row stored is the bottom of the picture.
    frame_rate
        The camera's recording rate, frames/s (``dFrameRate``, else ``FrameRate``), or None.
    decimation
        Recorded frames per saved image (1: none).
    times
        Seconds from the trigger, one per image.
    time_source
        ``"TIME64 block"`` (each image's own time) or ``"frame rate"`` (image numbers over the rate).
    exposures
        Exposure of each image, s (from a 1003 block), or None.
    trigger_time
        The trigger, UTC.
    levels
        ``(black, white)`` pixel values: the header's levels where it has sensible ones, else
        ``(0, 2**bit_depth - 1)``.
    image_offsets
        Byte offset of each image's annotation.
    frame_bytes
        Bytes of one image's pixels.
    setup
        The SETUP fields read (name -> value).
    """

    path: Path
    width: int
    height: int
    image_count: int
    first_image_no: int
    bit_depth: int
    storage: str
    bottom_up: bool
    frame_rate: float | None
    decimation: int
    times: np.ndarray
    time_source: str
    exposures: np.ndarray | None
    trigger_time: _dt.datetime
    levels: tuple[float, float]
    image_offsets: np.ndarray
    frame_bytes: int
    header: dict[str, Any] = field(default_factory=dict)
    setup: dict[str, Any] = field(default_factory=dict)
    mapped: MappedFile | None = field(default=None, repr=False, compare=False)

    @property
    def dtype(self) -> np.dtype:
        """The dtype of the frames :meth:`frame` returns."""
        return np.dtype(np.uint8) if self.storage == "8" else np.dtype(np.uint16)

    def frame(self, k: int) -> np.ndarray:
        """Image ``k`` (0-based in the file) as an (h, w) array, top row first, read through the file's memory
        map (its pages released once decoded)."""
        m = self.mapped
        off = int(self.image_offsets[k])
        ann = int(m.view(off, 4, k).view("<u4")[0])
        if ann < 8:
            raise _error(f"image {k}'s annotation declares {ann} bytes (at least 8: its size and the image's)",
                         m.label, field="AnnotationSize", frame=k)
        image_size = int(m.view(off + ann - 4, 4, k, recheck=False).view("<u4")[0])
        if image_size and image_size < self.frame_bytes:
            raise _error(f"image {k} declares {image_size} bytes of pixels; {self.width} x {self.height} "
                         f"pixels stored as {self.storage} take {self.frame_bytes}", m.label, field="ImageSize",
                         frame=k)
        start = off + ann
        out = self._decode(m.view(start, self.frame_bytes, k, recheck=False))
        m.release(off, ann + self.frame_bytes)
        return out

    def _decode(self, buf: np.ndarray) -> np.ndarray:
        h, w = self.height, self.width
        if self.storage == "8":
            img = buf.reshape(h, w)
        elif self.storage == "16":
            img = buf.view("<u2").reshape(h, w)
        else:
            return unpack(buf, int(self.storage[:2])).reshape(h, w)  # a new array, top row first
        # One copy out of the map, the rows turned the right way up on the way.
        return np.array(img[::-1] if self.bottom_up else img, dtype=self.dtype, order="C")

    @property
    def gaps(self) -> list[tuple[int, int]]:
        """``(k, missing)``: frames missing between image ``k`` and ``k + 1`` by their times."""
        return frame_gaps(self.times)


def _error(message: str, label: str, *, field: str | None = None, frame: int | None = None) -> CameraFileError:
    return CameraFileError(message, file=label, format="cine", field=field, frame=frame)


def _time64(value: int) -> tuple[int, int]:
    """(seconds, fraction in 2^-32 s) of a TIME64."""
    return value >> 32, value & 0xFFFFFFFF


def read_cine(path: str | Path, *, name: str | None = None) -> CineFile:
    """The header of a Phantom ``.cine`` file (the frames are read on demand, :meth:`CineFile.frame`).

    Parameters
    ----------
    path
        The file.
    name
        How to name it in errors (default: the path).

    Raises
    ------
    CameraFileError
        Not a ``.cine`` file, a truncated or damaged one (naming the field or
        image at fault), or a kind this reader does not read (JPEG-compressed,
        raw colour, an unknown packing).
    """
    path = Path(path)
    label = name or str(path)
    check_regular_file(path, label, max_bytes=sys.maxsize)  # a FIFO would hang the open, a device never end
    try:
        size = path.stat().st_size
        with open(path, "rb") as fp:
            head = fp.read(_HEADER.size)
            if len(head) < _HEADER.size:
                raise _error(f"not a Phantom .cine file: {size} bytes, shorter than its {_HEADER.size}-byte header",
                             label)
            (kind, header_size, compression, version, first_movie, total_count, first_no, count, off_bitmap,
             off_setup, off_offsets, trigger) = _HEADER.unpack(head)
            if kind != b"CI":
                raise _error(f"not a Phantom .cine file: it starts with {kind!r}, not b'CI'", label, field="Type")
            header = {"Headersize": header_size, "Compression": compression, "Version": version,
                      "FirstMovieImage": first_movie, "TotalImageCount": total_count, "FirstImageNo": first_no,
                      "ImageCount": count, "OffImageHeader": off_bitmap, "OffSetup": off_setup,
                      "OffImageOffsets": off_offsets}
            _check_header(header, size, label)
            fp.seek(off_bitmap)
            bitmap = _BITMAP.unpack(fp.read(_BITMAP.size))
            fp.seek(off_setup)
            setup_bytes = fp.read(max(off_offsets - off_setup, 0))
            fp.seek(off_offsets)
            table = fp.read(8 * count)
    except OSError as exc:
        raise _error(f"cannot read the file: {exc.strerror or exc}", label) from None
    _bi_size, width, height, _planes, bit_count, bi_compression, bi_size_image, *_ = bitmap
    if width <= 0 or height == 0 or width > 1 << 16 or abs(height) > 1 << 16:
        raise _error(f"its image header declares frames of {width} x {height} pixels", label,
                     field="biWidth" if width <= 0 or width > 1 << 16 else "biHeight")
    bottom_up = height > 0
    h, w = abs(height), width
    setup = _read_setup(setup_bytes, label)
    storage, bits_stored = _storage(bit_count, bi_compression, compression, setup, label)
    bit_depth = int(setup.get("RealBPP") or bits_stored)
    if not (8 <= bit_depth <= 16) or (storage == "8" and bit_depth != 8) or \
            (storage in ("10p", "12p") and bit_depth > bits_stored):
        raise _error(f"it declares {bit_depth} bits a pixel (RealBPP) for {storage}-bit storage", label,
                     field="RealBPP")
    n_pixels = h * w
    if storage in ("10p", "12p"):
        group = 4 if storage == "10p" else 2
        if n_pixels % group:
            raise _error(f"{w} x {h} pixels cannot be packed in whole groups of {group}", label,
                         field="biWidth")
        frame_bytes = packed_bytes(n_pixels, bits_stored)
    else:
        frame_bytes = n_pixels * (1 if storage == "8" else 2)
    if bi_size_image and bi_size_image < frame_bytes:
        raise _error(f"its image header declares {bi_size_image} bytes an image; {w} x {h} pixels as {storage} "
                     f"take {frame_bytes}", label, field="biSizeImage")
    if len(table) < 8 * count:
        raise _error(f"the file ends inside its table of {count} image offsets (truncated)", label,
                     field="OffImageOffsets")
    offsets = np.frombuffer(table, dtype="<i8").astype(np.int64)
    start = off_offsets + 8 * count
    bad = (offsets < start) | (offsets + 8 + frame_bytes > size)
    if bad.any():
        k = int(np.argmax(bad))
        if offsets[k] >= start and offsets[k] < size:
            raise _error(f"the file ends inside image {k} of {count}: it holds {size:,} bytes (truncated)", label,
                         frame=k)
        raise _error(f"image {k}'s offset {int(offsets[k]):,} lies outside the images (bytes {start:,} to "
                     f"{size:,})", label, field="ImageOffsets", frame=k)

    rate = _frame_rate(setup)
    decimation = max(int(setup.get("Decimation") or 1), 1)
    blocks = _tagged_blocks(path, off_setup + int(setup["Length"]), off_offsets, label)
    trig_s, trig_f = _time64(trigger)
    trigger_time = _dt.datetime.fromtimestamp(trig_s, _dt.timezone.utc) + _dt.timedelta(
        microseconds=trig_f / _FRACTION * 1e6)
    exposures = None
    if 1003 in blocks:
        data = blocks[1003]
        if len(data) < 4 * count:
            raise _error(f"its exposure block (type 1003) holds {len(data) // 4} exposures for {count} images",
                         label, field="TaggedBlock 1003")
        exposures = np.frombuffer(data[: 4 * count], dtype="<u4") / _FRACTION
    if 1002 in blocks:
        data = blocks[1002]
        if len(data) < 8 * count:
            raise _error(f"its time block (type 1002) holds {len(data) // 8} times for {count} images", label,
                         field="TaggedBlock 1002")
        stamps = np.frombuffer(data[: 8 * count], dtype="<u8")
        secs = (stamps >> np.uint64(32)).astype(np.int64) - trig_s
        frac = (stamps & np.uint64(0xFFFFFFFF)).astype(np.int64) - trig_f
        times = secs + frac / _FRACTION
        time_source = "TIME64 block"
        steps = np.diff(times)
        if count > 1 and not (steps > 0).all():
            k = int(np.argmax(steps <= 0))
            raise _error(f"its time block (type 1002) does not increase: image {k + 1} is at {times[k + 1]:.9g} s, "
                         f"image {k} at {times[k]:.9g} s", label, field="TaggedBlock 1002", frame=k + 1)
    elif rate is not None:
        times = (first_no + np.arange(count) * decimation) / rate
        time_source = "frame rate"
    else:
        raise _error("it records neither the frame rate (FrameRate, dFrameRate) nor the images' times "
                     "(a type 1002 block)", label, field="FrameRate")
    full = (1 << bit_depth) - 1
    black, white = setup.get("BlackLevel"), setup.get("WhiteLevel")
    levels = (float(black), float(white)) if black is not None and white is not None and \
        0 <= black < white <= full and white - black >= 16 else (0.0, float(full))
    return CineFile(path=path, width=w, height=h, image_count=count, first_image_no=first_no, bit_depth=bit_depth,
                    storage=storage, bottom_up=bottom_up and storage not in ("10p", "12p"), frame_rate=rate,
                    decimation=decimation, times=np.asarray(times, dtype=float), time_source=time_source,
                    exposures=exposures, trigger_time=trigger_time, levels=levels, image_offsets=offsets,
                    frame_bytes=frame_bytes, header=header, setup=setup, mapped=MappedFile(path, label, "cine"))


def _check_header(header: dict[str, int], size: int, label: str) -> None:
    if header["Headersize"] != _HEADER.size:
        raise _error(f"its header declares {header['Headersize']} bytes; a .cine header has {_HEADER.size}", label,
                     field="Headersize")
    if header["Compression"] == 1:
        raise _error("its images are JPEG-compressed (Compression 1); save the cine uncompressed in the camera "
                     "software", label, field="Compression")
    if header["Compression"] not in (0, 2):
        raise _error(f"unknown compression {header['Compression']} (0: grey, 2: uninterpolated)", label,
                     field="Compression")
    if header["Version"] != 1:
        raise _error(f"version {header['Version']} of the .cine format (this reader reads version 1, whose image "
                     "offsets are 64-bit)", label, field="Version")
    count = header["ImageCount"]
    if count == 0 or count > _MAX_IMAGES:
        raise _error(f"it declares {count} images", label, field="ImageCount")
    for key, low, span in (("OffImageHeader", _HEADER.size, _BITMAP.size), ("OffSetup", _HEADER.size, 144),
                           ("OffImageOffsets", _HEADER.size, 8 * count)):
        if not low <= header[key] <= size - span:
            raise _error(f"{key} {header[key]:,} lies outside the file ({size:,} bytes; truncated or damaged)",
                         label, field=key)


def _read_setup(data: bytes, label: str) -> dict[str, Any]:
    if len(data) < 144 or data[140:142] != b"ST":
        raise _error("its SETUP block has no 'ST' mark at byte 140 (damaged, or a .cine older than 1994)", label,
                     field="SETUP")
    length = struct.unpack_from("<H", data, 142)[0]
    if length < 144 or length > len(data):
        raise _error(f"its SETUP block declares {length} bytes; {len(data)} lie between it and the image offsets",
                     label, field="Length")
    out: dict[str, Any] = {}
    for key, (off, fmt) in _SETUP.items():
        if off + struct.calcsize(fmt) <= length:
            out[key] = struct.unpack_from(fmt, data, off)[0]
    return out


def _storage(bit_count: int, bi_compression: int, compression: int, setup: dict, label: str) -> tuple[str, int]:
    """How pixels are stored ("8", "16", "10p", "12p") and the bits each takes."""
    if compression == 2 and setup.get("CFA", 0) != 0:
        raise _error("an uninterpolated colour (raw Bayer) cine; save it interpolated in the camera software", label,
                     field="Compression")
    if bi_compression == 256:
        return "10p", 10
    if bi_compression == 1024:
        return "12p", 12
    if bi_compression != 0:
        raise _error(f"unknown pixel packing biCompression {bi_compression} (0, 256: 10-bit packed, 1024: 12-bit "
                     "packed)", label, field="biCompression")
    if bit_count in (8, 16):
        return str(bit_count), bit_count
    if bit_count in (24, 48):
        raise _error(f"a colour cine ({bit_count} bits a pixel); the tracker reads grey frames: save the clip grey "
                     "in the camera software", label, field="biBitCount")
    raise _error(f"{bit_count} bits a pixel in an unpacked image (biBitCount 8 or 16 for grey)", label,
                 field="biBitCount")


def _frame_rate(setup: dict) -> float | None:
    for key in ("dFrameRate", "FrameRate", "FrameRate16"):
        v = setup.get(key)
        if v is not None and np.isfinite(v) and 0 < v < 1e9:
            return float(v)
    return None


def _tagged_blocks(path: Path, start: int, stop: int, label: str) -> dict[int, bytes]:
    """The data of the tagged blocks between ``start`` and ``stop`` (type -> bytes; the first of each type)."""
    out: dict[int, bytes] = {}
    off = start
    with open(path, "rb") as fp:
        while off + 8 <= stop:
            fp.seek(off)
            block_size, kind, _reserved = struct.unpack("<IHH", fp.read(8))
            if block_size == 0 and kind == 0:
                break  # padding up to the image offsets
            if block_size < 8 or off + block_size > stop:
                raise _error(f"a tagged block at byte {off:,} declares {block_size} bytes, past the image offsets at "
                             f"{stop:,} (damaged)", label, field="BlockSize")
            if kind in (1002, 1003) and kind not in out:
                out[kind] = fp.read(block_size - 8)
            off += block_size
    return out


# ------------------------------------------------------------------------------------------------ writing


def write_cine(
    path: str | Path,
    frames: np.ndarray,
    *,
    fps: float,
    times: np.ndarray | None = None,
    first_image_no: int = 0,
    bit_depth: int | None = None,
    packing: int | None = None,
    decimation: int = 1,
    exposure: float | np.ndarray | None = None,
    trigger_time: _dt.datetime | None = None,
    levels: tuple[int, int] | None = None,
    annotation: bytes = b"",
    time_block: bool = True,
    exposure_block: bool = True,
    top_down: bool = False,
) -> Path:
    """Write grey frames as a Phantom ``.cine`` file (uncompressed, version 1), atomically.

    For tests, examples and rendered clips: what :func:`read_cine` and the
    camera maker's layout read.

    Parameters
    ----------
    path
        The file to write.
    frames
        (t, h, w) uint8 (8-bit) or uint16 frames (values below ``2**bit_depth``).
    fps
        The camera's recording rate, frames/s (``FrameRate`` and ``dFrameRate``).
    times
        Each frame's time from the trigger, s (default ``(first_image_no + i *
        decimation) / fps``): give a gap to record dropped frames.
    first_image_no
        Number of the first image (negative: frames before the trigger).
    bit_depth
        ``RealBPP`` (default 8 for uint8 frames, 16 otherwise).
    packing
        None (a byte or a 16-bit word a pixel), 10 or 12 (packed; ``bit_depth``
        must equal it).
    decimation
        The SETUP's ``Decimation``.
    exposure
        Exposure, s, one for all or one per frame (default: the frame period
        less 1 us).
    trigger_time
        The trigger, UTC (default 2024-05-01 12:00:00).
    levels
        ``(BlackLevel, WhiteLevel)`` (default 0 and ``2**bit_depth - 1``).
    annotation
        Bytes of each frame's annotation.
    time_block, exposure_block
        Write the 1002 (times) and 1003 (exposures) tagged blocks.
    top_down
        Store rows top-down (a negative ``biHeight``) instead of bottom-up.
    """
    arr = np.asarray(frames)
    if arr.ndim != 3 or arr.dtype not in (np.uint8, np.uint16):
        raise DataError(f"frames must be a (t, h, w) uint8 or uint16 array; got {arr.dtype} {arr.shape}",
                        option="frames")
    n, h, w = arr.shape
    bits = bit_depth if bit_depth is not None else (8 if arr.dtype == np.uint8 else 16)
    if packing not in (None, 10, 12) or (packing is not None and packing != bits):
        raise DataError(f"packing must be None, 10 or 12 and equal bit_depth; got {packing!r} with {bits}",
                        option="packing")
    if arr.dtype == np.uint8 and (bits != 8 or packing):
        raise DataError("8-bit frames are written with bit_depth 8 and no packing", option="bit_depth")
    if arr.dtype == np.uint16 and int(arr.max(initial=0)) >= 1 << bits:
        raise DataError(f"frames hold values up to {int(arr.max())}, more than {bits} bits", option="bit_depth")
    if times is None:  # a Decimation of 0 (old files) is none
        times = (first_image_no + np.arange(n) * max(decimation, 1)) / float(fps)
    times = np.asarray(times, dtype=float)
    trigger_time = trigger_time or _dt.datetime(2024, 5, 1, 12, 0, 0, tzinfo=_dt.timezone.utc)
    epoch = trigger_time.timestamp()
    trig_s = int(np.floor(epoch))
    trig_f = round((epoch - trig_s) * _FRACTION)
    trig_ticks = (trig_s << 32) + trig_f
    stamps = np.array([trig_ticks + round(float(t) * _FRACTION) for t in times], dtype=np.uint64)
    if exposure is None:
        exposure = max(max(decimation, 1) / float(fps) - 1e-6, 1e-6)
    exp_ticks = np.broadcast_to(np.rint(np.asarray(exposure, dtype=float) * _FRACTION), (n,)).astype("<u4")
    black, white = levels if levels is not None else (0, (1 << bits) - 1)

    setup_len = 10408
    setup = bytearray(setup_len)
    rate_int = round(fps)
    struct.pack_into("<H", setup, 0, min(rate_int, 65535))
    setup[140:142] = b"ST"
    struct.pack_into("<H", setup, 142, setup_len)
    struct.pack_into("<iI", setup, 429, first_image_no, n)
    struct.pack_into("<HH", setup, 737, w, h)
    struct.pack_into("<I", setup, 743, 12345)
    struct.pack_into("<I", setup, 768, rate_int)
    struct.pack_into("<I", setup, 772, round(float(np.mean(exp_ticks)) / _FRACTION * 1e6))
    struct.pack_into("<I", setup, 780, max(n + first_image_no, 0))
    struct.pack_into("<III", setup, 792, 603, 0, 800)  # camera, firmware and software versions
    struct.pack_into("<I", setup, 808, 0)  # CFA: a grey sensor
    struct.pack_into("<I", setup, 896, bits)
    struct.pack_into("<I", setup, 1556, decimation)
    struct.pack_into("<I", setup, 1568, round(float(np.mean(exp_ticks)) / _FRACTION * 1e9))
    setup[1596:1596 + 40] = b"written by bouncelab.tracking.write_cine"
    struct.pack_into("<ii", setup, 5732, black, white)
    struct.pack_into("<d", setup, 10400, float(fps))

    blocks = b""
    kinds = [(1002, stamps.astype("<u8").tobytes())] if time_block else []
    if exposure_block:
        kinds.append((1003, exp_ticks.tobytes()))
    for i, (kind, data) in enumerate(kinds):
        blocks += struct.pack("<IHH", 8 + len(data), kind, int(i < len(kinds) - 1)) + data

    if packing:
        frame_bytes = packed_bytes(h * w, packing)
    else:
        frame_bytes = h * w * arr.dtype.itemsize
    off_setup = _HEADER.size + _BITMAP.size
    off_offsets = off_setup + setup_len + len(blocks)
    ann = 8 + len(annotation)
    first = off_offsets + 8 * n
    offsets = first + np.arange(n, dtype=np.int64) * (ann + frame_bytes)
    bit_count = 8 if arr.dtype == np.uint8 else 16
    bi_compression = {None: 0, 10: 256, 12: 1024}[packing]
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:  # frame by frame: a long clip is not copied whole
        fh.write(_HEADER.pack(b"CI", _HEADER.size, 0, 1, first_image_no, n, first_image_no, n, _HEADER.size,
                              off_setup, off_offsets, trig_ticks))
        fh.write(_BITMAP.pack(40, w, -h if top_down else h, 1, bit_count, bi_compression, frame_bytes, 0, 0, 0, 0))
        fh.write(bytes(setup) + blocks + offsets.astype("<i8").tobytes())
        for k in range(n):
            img = arr[k] if top_down or packing else arr[k][::-1]
            fh.write(struct.pack("<I", ann) + annotation + struct.pack("<I", frame_bytes))
            fh.write(pack(img, packing).tobytes() if packing else
                     np.ascontiguousarray(img).astype("<u2" if bit_count == 16 else np.uint8).tobytes())
        fh.flush()
        os.fsync(fh.fileno())
    return Path(path)
