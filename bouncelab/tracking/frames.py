"""Reading a clip's frames: a camera file, a video file, a folder of images, a ``.npz``/``.npy`` file or an array.

:func:`open_clip` gives a :class:`Clip`, whose frames are read on demand, one at a
time, in passes over the clip: tracking holds a few frames at once (and the 31
frames the background is estimated from), not the whole clip, so its memory does
not grow with the clip's length. A clip whose frames fit in the memory budget
with room to spare is kept in memory after its first full pass, so a short clip
is decoded once. :func:`read_frames` reads a whole clip into one array.

Video files (AVI, MP4, MOV, MKV, ... as the camera software exports them, and
any other file FFmpeg reads) are decoded by PyAV where it is installed (the
``video`` extra; :mod:`bouncelab.tracking.pyav`), with the stream's timestamps
(:attr:`Clip.times`, ``time_source`` ``"stream timestamps"``: a container's,
often at a playback rate, so the camera's frame rate is still needed) and
streams of more than 8 bits as 16-bit grey; else by OpenCV's FFmpeg-backed
``VideoCapture`` (:data:`VIDEO_READER` chooses); image folders (PNG, TIFF,
BMP, JPEG) with ``cv2.imread``, in the order of the frame number in each file
name (the last group of digits), so ``frame_2.png`` comes before
``frame_10.png``; ``.npy`` files frame by frame from the file, ``.npz`` files
(a ``frames`` array) frame by frame from the compressed member.

High-speed cameras' own files, Phantom ``.cine`` (:mod:`bouncelab.tracking.cine`) and
Photron ``.mraw`` with its ``.cihx`` or ``.cih`` (:mod:`bouncelab.tracking.photron`),
are read frame by frame by memory map, with their frame times (:attr:`Clip.times`:
a ``.cine``'s TIME64 block shows frames the camera dropped), frame rate, bit depth
and header (:attr:`Clip.metadata`). Their frames keep every bit the camera recorded:
float32 grey levels on the 8-bit scale, mapped from the file's black and white
levels (a 12-bit value of 4095 is 255.0; one of 1 is 0.0623).

Colour frames are converted to grey. Frames of another type than 8-bit are
converted to 8 bits for the whole clip alike: floating-point frames within
[0, 1] are multiplied by 255; frames with values above 255 (16-bit cameras) are
scaled by the clip's largest value; others are rounded. Negative values (signed
or floating-point frames) are refused: no brightness is negative, and clipping
them at 0 would move the ball's edge without a word.

Memory
------
:data:`MEMORY_BUDGET` (1 GiB, per clip and process) bounds what a clip's frames
may take: tracking a clip needs about :data:`WORKING_BYTES_PER_PIXEL` bytes per
pixel of one frame whatever the clip's length (about 130 MB for 1920 x 1080), and
reading a whole clip (:func:`read_frames`) its frames' size. What would exceed the
budget is refused with a :class:`~bouncelab.core.errors.DataError` saying how much it
would take. Set ``bouncelab.tracking.frames.MEMORY_BUDGET`` (bytes), or pass
``memory_budget=`` to :func:`open_clip`, :func:`read_frames`,
:func:`~bouncelab.tracking.track_clip` or :func:`~bouncelab.tracking.measure_clips`,
to allow more.
"""

from __future__ import annotations

import os
import re
import stat
import sys
import zipfile
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from bouncelab.core.errors import DataError, Hint, MissingFileError
from bouncelab.core.files import check_regular_file
from bouncelab.tracking._cv import cv2
from bouncelab.tracking.pyav import wanted_frames
from bouncelab.tracking.rates import check_fps

__all__ = [
    "CAMERA_SUFFIXES",
    "IMAGE_SUFFIXES",
    "MEMORY_BUDGET",
    "VIDEO_SUFFIXES",
    "WORKING_BYTES_PER_PIXEL",
    "Clip",
    "open_clip",
    "read_frames",
]

IMAGE_SUFFIXES = (".png", ".tif", ".tiff", ".bmp", ".jpg", ".jpeg")
VIDEO_SUFFIXES = (".avi", ".mp4", ".mov", ".mkv", ".m4v", ".wmv", ".mpg", ".mpeg")
#: Files of frames saved with NumPy: a .npz of frames (and its fps) or a .npy array of frames.
ARRAY_SUFFIXES = (".npz", ".npy")
#: High-speed cameras' own files, which record their frame times: Phantom .cine, Photron .mraw (with its .cihx or
#: .cih header beside it; either file names the clip).
CAMERA_SUFFIXES = (".cine", ".mraw", ".cihx", ".cih")
#: Containers that store their frame count (a shortfall of more than one frame is a truncated file); others
#: (MPEG streams, WMV) only estimate it from the duration.
_COUNTED_VIDEO = (".avi", ".mp4", ".mov", ".m4v", ".mkv")

#: Which library decodes video files: ``"auto"`` (PyAV where it is installed, else OpenCV), ``"pyav"`` or
#: ``"opencv"``. PyAV gives the stream's timestamps and reads streams of more than 8 bits as 16-bit grey.
VIDEO_READER: str = "auto"

#: Memory, in bytes, that the frames of one clip may take in one process (1 GiB). Read at each call, so
#: setting it (``bouncelab.tracking.frames.MEMORY_BUDGET = 4 << 30``) applies to later calls.
MEMORY_BUDGET: int = 1 << 30

#: The hint of an error that a larger memory budget puts right (if the machine has the memory).
_MORE_MEMORY = Hint("memory_budget", None, "more bytes, if the machine has them (default: "
                                           "bouncelab.tracking.frames.MEMORY_BUDGET)")

#: Memory taken by tracking, per pixel of one frame (bytes): the background's 31 sampled frames (31), its
#: running quantile and float images (about 15), and the working copies of the frame being searched (about 15).
#: Measured: tracking a 1920 x 1080 clip peaks about 130 MB above the interpreter (benchmarks/bench_tracking_memory.py).
WORKING_BYTES_PER_PIXEL: int = 112


def working_bytes_per_pixel(dtype: np.dtype) -> int:
    """Memory taken by tracking, per pixel of one frame, for frames of ``dtype``: :data:`WORKING_BYTES_PER_PIXEL`
    for 8-bit frames; float32 frames (deep camera files) take 4 bytes a pixel for each of the background's
    sampled frames and its running quantile."""
    return WORKING_BYTES_PER_PIXEL + 40 * (np.dtype(dtype).itemsize - 1)

_GREY = np.array([0.299, 0.587, 0.114])


def _size(nbytes: float) -> str:
    """``nbytes`` for a person: ``1.2 GiB``, ``340 MiB``, ``12 KiB``."""
    for unit, scale in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if nbytes >= scale:
            v = nbytes / scale
            return f"{v:.3g} {unit}" if v < 100 else f"{v:.0f} {unit}"
    return f"{int(nbytes)} bytes"


def _budget(memory_budget: float | None) -> int:
    """The memory budget in bytes: ``memory_budget``, or :data:`MEMORY_BUDGET` read now."""
    value = MEMORY_BUDGET if memory_budget is None else memory_budget
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating) or not value > 0:
        raise DataError(f"memory_budget must be a positive number of bytes (e.g. 4 << 30 for 4 GiB); got {value!r}",
                        option="memory_budget")
    return int(min(value, 2**62))


# ---------------------------------------------------------------------------------------------------------
# Sources: where raw frames come from. Each yields (k, raw frame) for the frames asked, in order, one pass.
# ---------------------------------------------------------------------------------------------------------


class _Source:
    """Raw (h, w) frames of one kind of file, in frame order. ``kind``: the source array's dtype kind.

    A camera file also gives its frames' ``times`` (s), ``fps``, ``time_source``, ``bit_depth``, the
    pixel ``levels`` (black, white) that map its values to the clip's grey levels, and its ``metadata``; a
    rendered ``.npz`` clip its stored ``fps`` (without times)."""

    n: int
    h: int
    w: int
    dtype: np.dtype  # of the raw grey frames
    kind: str  # of the values as stored ("u", "i", "f"): decides the [0, 1] rule
    times: np.ndarray | None = None
    fps: float | None = None
    time_source: str | None = None
    bit_depth: int | None = None
    levels: tuple[float, float] | None = None
    metadata: dict[str, Any] = {}  # noqa: RUF012 - replaced, never changed in place

    def raw(self, wanted: Iterable[int] | None) -> Iterator[tuple[int, np.ndarray]]:
        raise NotImplementedError


def _check_dtype(dtype: np.dtype, label: str) -> None:
    if dtype.kind not in "uif" or dtype == np.bool_:
        raise DataError(f"frames must be numbers; got dtype {dtype}", file=label, option="frames")


def _frame_layout(shape: tuple[int, ...], label: str) -> tuple[int, int, int, int | None]:
    """(n, h, w, channels or None) of a (t, h, w) or (t, h, w, c) clip; DataError for another shape."""
    channels = None
    if len(shape) == 4 and shape[-1] in (1, 3, 4):
        channels = shape[-1]
        shape = shape[:3]
    if len(shape) != 3:
        raise DataError(f"frames must be (t, h, w) or (t, h, w, 3); got shape {tuple(shape)}", file=label,
                        option="frames")
    if shape[0] == 0 or shape[1] < 8 or shape[2] < 8:
        raise DataError(f"no frames, or frames smaller than 8 x 8 pixels: shape {tuple(shape)}", file=label)
    return int(shape[0]), int(shape[1]), int(shape[2]), channels


def _grey(frame: np.ndarray, channels: int | None) -> np.ndarray:
    if channels is None:
        return frame
    if channels == 1:
        return frame[..., 0]
    return frame[..., :3].astype(np.float64) @ _GREY


class _ArraySource(_Source):
    """An array in memory (or memory-mapped), (t, h, w) or (t, h, w, c)."""

    def __init__(self, arr: np.ndarray, label: str) -> None:
        _check_dtype(arr.dtype, label)
        self.n, self.h, self.w, self.channels = _frame_layout(arr.shape, label)
        self.arr = arr
        self.kind = arr.dtype.kind
        self.dtype = np.dtype(np.float64) if self.channels in (3, 4) else arr.dtype

    def raw(self, wanted):
        for k in range(self.n) if wanted is None else wanted:
            yield k, _grey(self.arr[k], self.channels)


def _npy_header(fp, label: str) -> tuple[tuple[int, ...], bool, np.dtype]:
    """Shape, Fortran order and dtype from the header of a ``.npy`` stream (DataError if unreadable)."""
    try:
        version = np.lib.format.read_magic(fp)
        if version == (1, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_1_0(fp)
        elif version == (2, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_2_0(fp)
        else:
            raise ValueError(f".npy format version {version} (bouncelab reads 1.0 and 2.0, as np.save writes)")
    except (ValueError, EOFError, OSError, zipfile.BadZipFile) as exc:
        raise DataError(f"cannot read the frames' .npy header (damaged or not a NumPy file): {exc}",
                        file=label) from None
    return tuple(int(s) for s in shape), bool(fortran), np.dtype(dtype)


class _NpySource(_Source):
    """A ``.npy`` file, read frame by frame with seeks (its pages are not kept mapped)."""

    def __init__(self, path: Path, label: str) -> None:
        self.path, self.label = path, label
        with open(path, "rb") as fp:
            shape, fortran, dtype = _npy_header(fp, label)
            self.offset = fp.tell()
        _check_dtype(dtype, label)
        self.n, self.h, self.w, self.channels = _frame_layout(shape, label)
        self.frame_shape = tuple(shape[1:])
        self.frame_bytes = int(np.prod(self.frame_shape)) * dtype.itemsize
        need = self.offset + self.n * self.frame_bytes
        size = path.stat().st_size
        if size < need:
            raise DataError(f"the file is truncated: its header declares {self.n} frames of shape "
                            f"{self.frame_shape}, {need:,} bytes with the header ({_size(need)}), but the file "
                            f"holds {size:,} bytes", file=label)
        self.file_dtype = dtype
        self.kind = dtype.kind
        self.dtype = np.dtype(np.float64) if self.channels in (3, 4) else dtype.newbyteorder("=")
        self.mapped = np.load(path, mmap_mode="r") if fortran and len(shape) > 1 else None

    def raw(self, wanted):
        if self.mapped is not None:  # Fortran order: a frame is scattered over the file; map it
            for k in range(self.n) if wanted is None else wanted:
                yield k, _grey(np.ascontiguousarray(self.mapped[k]), self.channels)
            return
        with open(self.path, "rb") as fp:
            for k in range(self.n) if wanted is None else wanted:
                fp.seek(self.offset + k * self.frame_bytes)
                buf = fp.read(self.frame_bytes)
                if len(buf) < self.frame_bytes:
                    raise DataError(f"the file ends inside frame {k} (truncated)", file=self.label)
                frame = np.frombuffer(buf, dtype=self.file_dtype).reshape(self.frame_shape)
                yield k, _grey(frame.astype(self.file_dtype.newbyteorder("="), copy=False), self.channels)


class _NpzSource(_Source):
    """The ``frames`` array of a ``.npz`` file, decompressed frame by frame in each pass."""

    def __init__(self, path: Path, label: str) -> None:
        self.path, self.label = path, label
        try:
            with zipfile.ZipFile(path) as zf:
                names = zf.namelist()
                if "frames.npy" not in names:
                    arrays = [n[:-4] for n in names if n.endswith(".npy")]
                    raise DataError(f"the .npz file has no 'frames' array (it has {arrays})", file=label)
                info = zf.getinfo("frames.npy")
                with zf.open(info) as fp:
                    shape, fortran, dtype = _npy_header(fp, label)
                    self.offset = fp.tell()
        except (zipfile.BadZipFile, zipfile.LargeZipFile, OSError, EOFError, ValueError) as exc:
            raise DataError(f"cannot read the .npz file (truncated or damaged): {exc}", file=label) from None
        _check_dtype(dtype, label)
        self.n, self.h, self.w, self.channels = _frame_layout(shape, label)
        self.frame_shape = tuple(shape[1:])
        self.frame_bytes = int(np.prod(self.frame_shape)) * dtype.itemsize
        need = self.offset + self.n * self.frame_bytes
        if info.file_size < need:
            raise DataError(f"the 'frames' array is truncated: its header declares {self.n} frames of shape "
                            f"{self.frame_shape}, {need:,} bytes with the header ({_size(need)}), but the archive "
                            f"holds {info.file_size:,} bytes of it", file=label)
        self.fortran = fortran and len(shape) > 1
        self.file_dtype = dtype
        self.kind = dtype.kind
        stored = stored_fps(path)  # a rendered clip's rate (no times: frame_times reconciles it with an fps given)
        self.fps = None if stored is None else check_fps(stored, label, "clip file")
        self.dtype = np.dtype(np.float64) if self.channels in (3, 4) else dtype.newbyteorder("=")

    def raw(self, wanted):
        if self.fortran:
            raise DataError("the 'frames' array is stored in Fortran order; save it with "
                            "np.savez_compressed(path, frames=np.ascontiguousarray(frames))", file=self.label)
        want = None if wanted is None else set(wanted)
        last = self.n - 1 if want is None else max(want, default=-1)
        try:
            with zipfile.ZipFile(self.path) as zf, zf.open("frames.npy") as fp:
                fp.read(self.offset)
                for k in range(last + 1):
                    buf = fp.read(self.frame_bytes)
                    if len(buf) < self.frame_bytes:
                        raise DataError(f"the 'frames' array ends inside frame {k} (truncated)", file=self.label)
                    if want is None or k in want:
                        frame = np.frombuffer(buf, dtype=self.file_dtype).reshape(self.frame_shape)
                        yield k, _grey(frame.astype(self.file_dtype.newbyteorder("="), copy=False),
                                       self.channels)
        except (zipfile.BadZipFile, OSError, EOFError, ValueError) as exc:  # e.g. a bad CRC or a cut stream
            raise DataError(f"cannot read the frames (truncated or damaged .npz): {exc}", file=self.label) from None


def _read_image(path: Path, label: str) -> np.ndarray:
    check_regular_file(path, label)  # a FIFO named frame1.png would hang the read, a device never end
    img = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if img is None:
        raise DataError("cannot read the image (damaged or not an image)", file=label)
    if img.ndim == 3:
        img = cv2.cvtColor(img[..., :3], cv2.COLOR_BGR2GRAY)
    return img


def _frame_number(path: Path) -> tuple[int, str]:
    digits = re.findall(r"\d+", path.stem)
    return (int(digits[-1]) if digits else -1, path.name)


class _FolderSource(_Source):
    """A folder of images, one frame per image, read one image at a time."""

    def __init__(self, path: Path, label: str) -> None:
        files = sorted((p for p in path.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES), key=_frame_number)
        if not files:
            raise DataError(f"no images ({', '.join(IMAGE_SUFFIXES)}) in the folder", file=label)
        self.files, self.label = files, label
        first = _read_image(files[0], f"{label}/{files[0].name}")
        _check_dtype(first.dtype, label)
        self.n, self.h, self.w, _ = _frame_layout((len(files), *first.shape), label)
        self.dtype = first.dtype
        self.kind = first.dtype.kind

    def raw(self, wanted):
        for k in range(self.n) if wanted is None else wanted:
            f = self.files[k]
            img = _read_image(f, f"{self.label}/{f.name}")
            if img.shape != (self.h, self.w):
                raise DataError(f"frame {k} is {img.shape[1]} x {img.shape[0]} pixels; the first is "
                                f"{self.w} x {self.h}", file=f"{self.label}/{f.name}")
            if img.dtype != self.dtype:  # mixing 8- and 16-bit images would scale some of them wrongly
                raise DataError(f"frame {k} has pixels of type {img.dtype}; the first image's are {self.dtype}",
                                file=f"{self.label}/{f.name}")
            yield k, img


class _VideoSource(_Source):
    """A video file, decoded in order in each pass (frames not asked for are grabbed, not converted)."""

    def __init__(self, path: Path, label: str, prefetch, keep_bytes: int) -> None:
        self.path, self.label = path, label
        cap = cv2.VideoCapture(str(path))
        try:
            if not cap.isOpened():
                raise DataError("cannot open the video (unknown format or damaged file)", file=label)
            declared = int(max(cap.get(cv2.CAP_PROP_FRAME_COUNT), 0))
            self.h = int(cap.get(cv2.CAP_PROP_FRAME_HEIGHT))
            self.w = int(cap.get(cv2.CAP_PROP_FRAME_WIDTH))
            # One pass counts the frames (a container's count can be an estimate), keeps them all if they take
            # at most ``keep_bytes`` (a short clip is decoded once), and otherwise reads only the frames that
            # ``prefetch`` asks for (those of the declared count), so that no other pass is needed for them.
            want = set(prefetch(declared)) if declared and prefetch is not None else set()
            self.prefetched: dict[int, np.ndarray] = {}
            # keep the frames only if the count the container declares fits (an unknown count: try)
            kept: list[np.ndarray] | None = [] if declared * self.h * self.w <= keep_bytes else None
            n = 0
            while True:
                if kept is not None and (n + 1) * self.h * self.w > keep_bytes:
                    kept = None  # too long to keep: stream it
                if kept is not None or n in want:
                    ok, img = cap.read()
                    if ok:
                        img = self._grey(img)
                        if kept is not None:
                            kept.append(img)
                        if n in want:
                            self.prefetched[n] = img
                else:
                    ok = cap.grab()
                if not ok:
                    break
                n += 1
        finally:
            cap.release()
        if n == 0:
            raise DataError("the video has no readable frame (damaged file or unsupported codec)", file=label)
        if path.suffix.lower() in _COUNTED_VIDEO and declared and n < declared - 1:
            raise DataError(f"the video holds {n} readable frames of the {declared} its header declares "
                            "(truncated or damaged file)", file=label)
        if n != declared:
            self.prefetched = {}  # read for a count that was not the real one
        self.kept = kept
        self.n = n
        _frame_layout((n, self.h, self.w), label)
        self.dtype = np.dtype(np.uint8)
        self.kind = "u"

    @staticmethod
    def _grey(img: np.ndarray) -> np.ndarray:
        return cv2.cvtColor(img, cv2.COLOR_BGR2GRAY) if img.ndim == 3 else img

    def raw(self, wanted):
        return wanted_frames(self, wanted, self._decode)

    def _decode(self, wanted_set: set[int] | None, last: int) -> Iterator[tuple[int, np.ndarray]]:
        cap = cv2.VideoCapture(str(self.path))
        try:
            for k in range(last + 1):
                if wanted_set is None or k in wanted_set:
                    ok, img = cap.read()
                    if ok:
                        img = self._grey(img)
                else:
                    ok = cap.grab()
                if not ok:
                    raise DataError(f"the video could be read to its end once but not again at frame {k} "
                                    "(changed or damaged file)", file=self.label)
                if wanted_set is None or k in wanted_set:
                    if img.shape != (self.h, self.w):
                        raise DataError(f"frame {k} is {img.shape[1]} x {img.shape[0]} pixels; the video "
                                        f"declares {self.w} x {self.h}", file=self.label)
                    yield k, img
        finally:
            cap.release()


class _PyAVSource(_Source):
    """Any video FFmpeg reads, decoded by PyAV (:mod:`bouncelab.tracking.pyav`), with its stream timestamps."""

    def __init__(self, path: Path, label: str, prefetch, keep_bytes: int) -> None:
        from bouncelab.tracking.pyav import AVVideo

        self.video = video = AVVideo(path, label, prefetch, keep_bytes)
        self.n, self.h, self.w = video.n, video.h, video.w
        _frame_layout((self.n, self.h, self.w), label)
        self.dtype = video.dtype
        self.kind = "u"
        self.kept = video.kept
        video.kept = None
        self.times = video.times
        self.time_source = None if video.times is None else "stream timestamps"
        self.bit_depth = video.bit_depth
        self.levels = (0.0, 65535.0) if video.deep else None  # deeper streams are read as 16-bit grey
        self.metadata = {"format": "video (read by PyAV/FFmpeg)", "container_frame_rate": video.container_fps,
                         "time_base": video.time_base}

    def raw(self, wanted):
        yield from self.video.frames(wanted)


class _CameraSource(_Source):
    """A camera file (Phantom ``.cine``, Photron ``.mraw``): frames by memory map, with their times."""

    def __init__(self, path: Path, label: str) -> None:
        from bouncelab.tracking.cine import CINE_SUFFIXES, read_cine
        from bouncelab.tracking.photron import read_mraw

        self.label = label
        if path.suffix.lower() in CINE_SUFFIXES:
            f: Any = read_cine(path, name=label)
            self.n = f.image_count
            self.fps = f.frame_rate / f.decimation if f.frame_rate else None
            self.metadata = _cine_metadata(f)
        else:
            f = read_mraw(path, name=label if path.suffix.lower() == ".mraw" else None)
            self.n = f.frame_count
            self.fps = f.frame_rate
            self.metadata = _mraw_metadata(f)
        self.file = f
        self.h, self.w = f.height, f.width
        _frame_layout((self.n, self.h, self.w), label)
        self.dtype = f.dtype
        self.kind = "u"
        self.times = np.asarray(f.times, dtype=float)
        self.time_source = getattr(f, "time_source", "frame rate")
        if self.time_source == "TIME64 block":
            steps = np.diff(self.times)
            if steps.size:
                # The times are the truth; the rate is theirs (a header's rate can be rounded or decimated).
                from bouncelab.tracking.camera import frame_gaps

                whole = steps.size + sum(m for _, m in frame_gaps(self.times))
                rate = whole / float(self.times[-1] - self.times[0])
                if self.fps is None or abs(rate / self.fps - 1.0) > 1e-4:  # the header's, unless the times differ
                    self.fps = rate
        self.bit_depth = f.bit_depth
        self.levels = f.levels

    def raw(self, wanted):
        for k in range(self.n) if wanted is None else wanted:
            yield k, self.file.frame(k)


def _cine_metadata(f) -> dict[str, Any]:
    meta: dict[str, Any] = {
        "format": "Phantom cine",
        "first_image_no": f.first_image_no,
        "trigger_time": f.trigger_time.isoformat(timespec="microseconds"),
        "storage": {"8": "8-bit", "16": "16-bit words", "10p": "10-bit packed", "12p": "12-bit packed"}[f.storage],
        "header_frame_rate": f.frame_rate,
        "decimation": f.decimation,
        "time_source": f.time_source,
        "rows": "bottom-up" if f.bottom_up else "top-down",
        "levels": f.levels,
    }
    if f.exposures is not None:
        meta["exposure_s"] = float(np.median(f.exposures))
    for key in ("Serial", "CameraVersion", "SoftwareVersion", "ShutterNs", "bFlipH", "bFlipV"):
        if key in f.setup:
            meta[key] = f.setup[key]
    return meta


def _mraw_metadata(f) -> dict[str, Any]:
    meta: dict[str, Any] = {
        "format": "Photron mraw",
        "header": f.header_path.name,
        "start_frame": f.start_frame,
        "storage": {8: "8-bit", 12: "12-bit packed", 16: "16-bit words"}[f.storage_bits],
        "header_frame_rate": f.frame_rate,
        "time_source": "frame rate",
        "rows": "top-down",
        "levels": f.levels,
    }
    for key in ("Camera Type", "Date", "Time", "Shutter Speed(s)"):
        if key in f.header:
            meta[key] = f.header[key]
    return meta


# ---------------------------------------------------------------------------------------------------------
# The clip
# ---------------------------------------------------------------------------------------------------------


class Clip:
    """A clip's grey frames, read on demand (from :func:`open_clip`), with its times and header.

    Frames come in passes over the clip (:meth:`frames`), so tracking holds a
    few frames at a time, not the clip. A clip whose frames take at most half
    the memory budget is kept in memory after its first full pass. Indexing
    (``clip[k]``, ``clip[[0, 5, 9]]``, ``clip[2:6]``) reads those frames;
    :meth:`read` reads them all.

    Frames are grey levels on the 8-bit scale, 0 (black) to 255 (white): uint8
    for 8-bit sources, and float32 for a camera file of more bits (``.cine``,
    ``.mraw``), mapped from its black and white levels without rounding, so
    that detection sees every bit the camera recorded.

    Attributes
    ----------
    name
        The clip's name in errors.
    shape
        ``(t, h, w)``: frames, height and width (pixels).
    dtype
        uint8, or float32 for a camera file of more than 8 bits.
    memory_budget
        Bytes the clip's frames may take (see :data:`MEMORY_BUDGET`).
    times
        Each frame's time, s, as the file records it (a ``.cine``'s TIME64
        block, from the trigger; a ``.mraw``'s start frame over its record
        rate), or None (the file records none: give the frame rate).
    fps
        The file's frame rate, frames/s (from its times where it has them; a
        rendered ``.npz`` clip's stored ``fps``), or None.
    time_source
        Where ``times`` come from: ``"TIME64 block"``, ``"frame rate"`` (the
        header's rate and frame numbers), or None.
    bit_depth
        Bits a pixel holds in the file (8 for 8-bit sources; None when not known).
    metadata
        The header's facts (format, trigger time, storage, exposure, camera...).
    """

    ndim = 3

    def __init__(self, source: _Source, name: str, memory_budget: int) -> None:
        self._src = source
        self.name = name
        self.shape = (source.n, source.h, source.w)
        self.memory_budget = memory_budget
        self.times = None if source.times is None else np.asarray(source.times, dtype=float)
        self.fps = source.fps
        self.time_source = source.time_source
        self.bit_depth = source.bit_depth if source.bit_depth is not None else (
            8 if source.dtype == np.uint8 else None)
        self.metadata = dict(source.metadata)
        self._scale: float | None = None
        self._levels = source.levels
        deep = source.levels is not None and not (source.dtype == np.uint8 and tuple(source.levels) == (0, 255))
        self.dtype = np.dtype(np.float32) if deep else np.dtype(np.uint8)
        self._checked = source.dtype == np.uint8 or source.levels is not None
        self._cache: np.ndarray | None = None
        if isinstance(source, _ArraySource) and source.arr.dtype == np.uint8 and source.channels is None:
            self._cache = source.arr  # already 8-bit grey frames in memory
        elif isinstance(source, _VideoSource | _PyAVSource) and source.kept is not None:
            if any(f.shape != (source.h, source.w) for f in source.kept):
                raise DataError(f"the video's frames are not all {source.w} x {source.h} pixels", file=name)
            self._cache = np.empty(self.shape, self.dtype)
            for k in range(source.n):  # frame by frame, freeing each decoded frame: never twice the clip
                self._cache[k] = self._convert(source.kept[k])
                source.kept[k] = None
            source.kept = None

    def __len__(self) -> int:
        return self.shape[0]

    def __repr__(self) -> str:
        n, h, w = self.shape
        rate = "" if self.fps is None else f" at {self.fps:g} frames/s"
        bits = "" if self.bit_depth is None or self.bit_depth == 8 else f", {self.bit_depth}-bit"
        return f"<Clip {self.name!r}: {n} frames of {w} x {h}{rate}{bits}>"

    def describe(self) -> str:
        """The clip's header in a few lines: size, frames, rate, bit depth, trigger, exposure, dropped frames
        (what ``bouncelab info clip.cine`` prints)."""
        n, h, w = self.shape
        meta = self.metadata
        lines = [f"{self.name}: {meta.get('format', 'clip')}"]
        numbers = ""
        if "first_image_no" in meta:
            numbers = f" (images {meta['first_image_no']} to {meta['first_image_no'] + n - 1})"
        elif "start_frame" in meta:
            numbers = f" (frames {meta['start_frame']} to {meta['start_frame'] + n - 1})"
        lines.append(f"  frames: {n} of {w} x {h} pixels{numbers}")
        if self.fps is not None:
            rate = f"  frame rate: {self.fps:.6g} frames/s"
            header = meta.get("header_frame_rate")
            if self.time_source == "TIME64 block":
                rate += " (from the times of its TIME64 block"
                rate += f"; header {header:.6g} frames/s" if header else ""
                rate += f", decimation {meta['decimation']}" if meta.get("decimation", 1) > 1 else ""
                rate += ")"
            elif self.time_source == "frame rate":
                rate += " (its header's; no per-frame times: frame numbers over the rate)"
            lines.append(rate)
        if self.times is not None and n:
            lines.append(f"  times: {self.times[0]:.6g} s to {self.times[-1]:.6g} s from the trigger")
        if self.bit_depth is not None:
            bits = f"  bit depth: {self.bit_depth} bits"
            if "storage" in meta:
                bits += f" ({meta['storage']})"
            if "levels" in meta:
                bits += f"; black and white levels {meta['levels'][0]:g} and {meta['levels'][1]:g}"
            lines.append(bits)
        if "trigger_time" in meta:
            lines.append(f"  trigger: {meta['trigger_time']}")
        if "exposure_s" in meta:
            lines.append(f"  exposure: {meta['exposure_s'] * 1e6:.4g} us")
        elif "Shutter Speed(s)" in meta:
            lines.append(f"  shutter: {meta['Shutter Speed(s)']} s")
        if self.time_source == "TIME64 block":
            gaps = self.gaps
            if gaps:
                where = ", ".join(f"{m} after frame {k} ({self.times[k]:.6g} s)" for k, m in gaps)
                lines.append(f"  dropped frames: {sum(m for _, m in gaps)} ({where})")
            else:
                lines.append("  dropped frames: none")
        elif self.times is not None:
            lines.append("  dropped frames: not recorded (the file has no per-frame times)")
        if "rows" in meta:
            lines.append(f"  rows stored: {meta['rows']}")
        camera = [f"{k} {meta[k]}" for k in ("Camera Type", "Serial", "CameraVersion", "SoftwareVersion")
                  if k in meta]
        if camera:
            lines.append("  camera: " + ", ".join(camera))
        return "\n".join(lines)

    @property
    def gaps(self) -> list[tuple[int, int]]:
        """``(k, missing)``: frames the camera did not record between frame ``k`` and ``k + 1``, from the
        file's times (empty without times)."""
        from bouncelab.tracking.camera import frame_gaps

        return [] if self.times is None else frame_gaps(self.times)

    @property
    def in_memory(self) -> bool:
        """Whether the frames are held in memory (or will be, from the first full pass on)."""
        return self._cache is not None or self.nbytes <= self.memory_budget // 2

    @property
    def nbytes(self) -> int:
        """Bytes of all the clip's frames (as :attr:`dtype`)."""
        n, h, w = self.shape
        return n * h * w * self.dtype.itemsize

    def frames(self, indices: Iterable[int] | None = None) -> Iterator[tuple[int, np.ndarray]]:
        """``(k, frame)`` for the frames ``indices`` (default: all), in increasing order, in one pass.

        Raises
        ------
        DataError
            A frame that cannot be read (damaged or truncated file, a damaged
            image), or values that cannot be brightness (negative, NaN).
        """
        want = None if indices is None else sorted({self._index(k) for k in indices})
        if self._cache is not None:
            for k in range(len(self)) if want is None else want:
                yield k, self._cache[k]
            return
        self._check_values()
        fill = want is None and self.nbytes <= self.memory_budget // 2
        cache = np.empty(self.shape, self.dtype) if fill else None
        for k, raw in self._src.raw(want):
            frame = self._convert(raw)
            if cache is not None:
                cache[k] = frame
            yield k, frame
        if cache is not None:
            self._cache = cache  # a complete pass: later passes read memory, not the file

    def take(self, indices: Iterable[int]) -> np.ndarray:
        """The frames ``indices`` (in the order given) as a (len, h, w) array of :attr:`dtype`."""
        order = [self._index(k) for k in indices]
        if self._cache is None and self.nbytes <= self.memory_budget // 2:
            for _ in self.frames():  # a clip that will be kept: read it whole now, once
                pass
        at: dict[int, list[int]] = {}
        for i, k in enumerate(order):
            at.setdefault(k, []).append(i)
        _, h, w = self.shape
        out = np.empty((len(order), h, w), self.dtype)
        for k, frame in self.frames(order):  # straight into place: no second copy of the frames
            out[at[k]] = frame
        return out

    def __getitem__(self, key: Any) -> np.ndarray:
        if isinstance(key, int | np.integer) and not isinstance(key, bool):
            return self.take([int(key)])[0]
        if isinstance(key, slice):
            return self.take(range(*key.indices(len(self))))
        return self.take(np.asarray(key, dtype=int).ravel().tolist())

    def __iter__(self) -> Iterator[np.ndarray]:
        for _, frame in self.frames():
            yield frame

    def read(self) -> np.ndarray:
        """All frames as a (t, h, w) array of :attr:`dtype` (uint8, or float32 for a deeper camera file).

        Raises
        ------
        DataError
            The frames would take more than the memory budget (the message
            says how much), or as :meth:`frames`.
        """
        if self._cache is not None:
            return np.ascontiguousarray(self._cache)
        n, h, w = self.shape
        if self.nbytes > self.memory_budget:
            raise DataError(f"reading all {n} frames of {w} x {h} pixels would take {_size(self.nbytes)}, more than "
                            f"the memory budget of {_size(self.memory_budget)}; track_clip and measure_clips read "
                            "a clip frame by frame (give them the file)", file=self.name, option="memory_budget",
                            hints=[_MORE_MEMORY])
        out = np.empty(self.shape, self.dtype)
        for k, frame in self.frames():
            out[k] = frame
        return out

    def check_working_memory(self) -> None:
        """DataError if tracking frames of this size needs more than the memory budget (saying how much)."""
        n, h, w = self.shape
        per_pixel = working_bytes_per_pixel(self.dtype)
        need = per_pixel * h * w + 128 * n  # + the track's per-frame arrays
        if need > self.memory_budget:
            raise DataError(f"tracking frames of {w} x {h} pixels takes about {_size(need)} of memory "
                            f"({per_pixel} bytes a pixel: the background's sampled frames and working "
                            f"copies of a frame), more than the memory budget of {_size(self.memory_budget)}",
                            file=self.name, option="memory_budget", hints=[_MORE_MEMORY])

    # -------------------------------------------------------------- conversion to grey levels
    def _index(self, k: int) -> int:
        n = len(self)
        kk = int(k)
        if kk < 0:
            kk += n
        if not 0 <= kk < n:
            raise IndexError(f"frame {k} of a clip of {n} frames")
        return kk

    def _check_values(self) -> None:
        """One pass over a clip of another type than 8-bit: refuse NaN and negative values, and set the
        scale to 8 bits from the clip's range (the same for every frame)."""
        if self._checked:
            return
        src = self._src
        lo, hi = np.inf, -np.inf
        negative = None
        for k, raw in src.raw(None):
            a = np.asarray(raw)
            if a.dtype.kind == "f" and not np.isfinite(a).all():
                raise DataError(f"frame {k} has NaN or infinite pixels", file=self.name)
            mn, mx = float(a.min()), float(a.max())
            if mn < 0 and negative is None:
                negative = (k, mn)
            lo, hi = min(lo, mn), max(hi, mx)
        if negative is not None:
            k, mn = negative
            raise DataError(f"frames of type {src.dtype} with negative values (first in frame {k}: {mn:g}; "
                            f"smallest {lo:g}): pixels are brightness, never negative, and clipping them at 0 "
                            "would move the ball's edge. Convert them yourself to 0..255 (e.g. subtract the "
                            "clip's minimum, or take an unsigned camera export)", file=self.name)
        if src.kind == "f" and hi <= 1.0 and lo >= 0.0:
            self._scale = 255.0  # floating-point images in [0, 1]
        elif hi > 255.0:
            self._scale = 255.0 / hi  # 16-bit (or wider) frames: scale by the clip's largest value
        self._checked = True

    def _convert(self, raw: np.ndarray) -> np.ndarray:
        if self.dtype == np.float32:  # a deep camera file: its levels to 0..255, every bit kept
            black, white = self._levels
            out = raw.astype(np.float32)
            out -= np.float32(black)
            out *= np.float32(255.0 / (white - black))
            return out
        if raw.dtype == np.uint8:
            return np.ascontiguousarray(raw)
        a = raw.astype(np.float64)
        if self._scale is not None:
            a = a * self._scale
        return np.clip(np.rint(a), 0, 255).astype(np.uint8)


def open_clip(source, *, name: str | None = None, memory_budget: float | None = None) -> Clip:
    """A clip's frames, read on demand (:class:`Clip`).

    Parameters
    ----------
    source
        A Phantom ``.cine``, a Photron ``.mraw`` (or its ``.cihx``/``.cih``
        header), a video file, a folder of images, an image, a ``.npy`` file, a
        ``.npz`` file holding a ``frames`` array, an array (t, h, w) or
        (t, h, w, 3) (RGB), or a :class:`Clip` (returned as it is).
    name
        How to name the source in errors (default: the path).
    memory_budget
        Bytes the clip's frames may take (default :data:`MEMORY_BUDGET`).

    Returns
    -------
    Clip

    Raises
    ------
    DataError
        A missing, unreadable, truncated or damaged file or folder (naming the
        file and, for a folder, the image that failed), an unknown format, an
        array of the wrong shape or type, or a bad ``memory_budget``; a
        :class:`~bouncelab.tracking.camera.CameraFileError` (a DataError naming
        the file, its format and the header field or frame at fault) for a
        camera file.
    """
    if isinstance(source, Clip):
        return source
    budget = _budget(memory_budget)
    if isinstance(source, np.ndarray):
        return Clip(_ArraySource(source, name or "array"), name or "array", budget)
    path = Path(source)
    label = name or str(path)
    if not path.exists():
        raise MissingFileError("no such file or folder", file=label)
    if path.is_dir():
        return Clip(_FolderSource(path, label), label, budget)
    check_regular_file(path, label, max_bytes=sys.maxsize)  # no FIFO or device; any size (read frame by frame)
    suffix = path.suffix.lower()
    try:
        if suffix in CAMERA_SUFFIXES:
            src: _Source = _CameraSource(path, label)
        elif suffix == ".npy":
            src = _NpySource(path, label)
        elif suffix == ".npz":
            src = _NpzSource(path, label)
        elif suffix in IMAGE_SUFFIXES:
            src = _ArraySource(_read_image(path, label)[None], label)
        else:
            from bouncelab.tracking.detect import background_indices
            from bouncelab.tracking.pyav import have_pyav

            reader = _PyAVSource if VIDEO_READER == "pyav" or (VIDEO_READER == "auto" and have_pyav()) \
                else _VideoSource
            src = reader(path, label, prefetch=background_indices, keep_bytes=budget // 2)
    except PermissionError:
        raise DataError("permission denied: the file cannot be read", file=label) from None
    except IsADirectoryError:  # pragma: no cover - checked above
        raise DataError("a folder, not a file", file=label) from None
    return Clip(src, label, budget)


def read_frames(source, *, name: str | None = None, memory_budget: float | None = None) -> np.ndarray:
    """Frames of a clip as one (t, h, w) uint8 array.

    Tracking does not need this: :func:`~bouncelab.tracking.track_clip` reads a
    clip frame by frame (:func:`open_clip`).

    Parameters
    ----------
    source
        A video file, a folder of images, a ``.npz``/``.npy`` file holding a
        ``frames`` array, or an array (t, h, w) or (t, h, w, 3) (RGB).
    name
        How to name the source in errors (default: the path).
    memory_budget
        Bytes the frames may take (default :data:`MEMORY_BUDGET`).

    Returns
    -------
    numpy.ndarray
        (t, h, w) grey frames: uint8, or float32 on the same 0-255 scale for a
        camera file of more than 8 bits (:class:`Clip`).

    Raises
    ------
    DataError
        A missing, unreadable, truncated or damaged file or folder (naming the
        file and, for a folder, the image that failed), an unknown format,
        frames of unequal size, an array of the wrong shape or type, negative
        or NaN pixel values, or frames that would take more than the memory
        budget (saying how much).
    """
    return open_clip(source, name=name, memory_budget=memory_budget).read()


def stored_fps(source) -> Any:
    """The ``fps`` entry an ``.npz`` clip carries (as ``RenderedClip.save`` writes it), as stored: a number, or
    whatever a hostile file holds there (:func:`~bouncelab.tracking.rates.check_fps` judges it where the clip is
    opened); None for another kind of clip, a file without that entry, or an unreadable one (reading the frames
    says why)."""
    if not isinstance(source, str | Path) or Path(source).suffix.lower() != ".npz":
        return None
    try:
        if not stat.S_ISREG(os.stat(source).st_mode):  # a FIFO would hang np.load: reading the frames says why
            return None
        with np.load(source, allow_pickle=False) as data:
            if "fps" not in data.files:
                return None
            fps = data["fps"]
    except (OSError, ValueError, TypeError, KeyError, AttributeError, EOFError, zipfile.BadZipFile):
        return None
    return fps.item() if fps.ndim == 0 else fps  # one number as a Python scalar (messages show it as such)
