"""Reading a clip's frames: a video file, a folder of images, or an array (:func:`read_frames`).

Video files (AVI, MP4, MOV, MKV, ... as the camera software exports them) are
read with OpenCV's FFmpeg-backed ``VideoCapture``; image folders (PNG, TIFF,
BMP, JPEG) with ``cv2.imread``, in the order of the frame number in each file
name (the last group of digits), so ``frame_2.png`` comes before
``frame_10.png``. Colour frames are converted to grey; 16-bit frames are scaled
to 8 bits by the clip's largest value.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from bouncelab.errors import DataError
from bouncelab.tracking._cv import cv2

__all__ = ["IMAGE_SUFFIXES", "VIDEO_SUFFIXES", "read_frames"]

IMAGE_SUFFIXES = (".png", ".tif", ".tiff", ".bmp", ".jpg", ".jpeg")
VIDEO_SUFFIXES = (".avi", ".mp4", ".mov", ".mkv", ".m4v", ".wmv", ".mpg", ".mpeg")
_NPZ_SUFFIXES = (".npz", ".npy")


def read_frames(source, *, name: str | None = None) -> np.ndarray:
    """Frames of a clip as a (t, h, w) uint8 array.

    Parameters
    ----------
    source
        A video file, a folder of images, a ``.npz``/``.npy`` file holding a
        ``frames`` array, or an array (t, h, w) or (t, h, w, 3) (RGB).
    name
        How to name the source in errors (default: the path).

    Returns
    -------
    numpy.ndarray
        (t, h, w) uint8 grey frames.

    Raises
    ------
    DataError
        A missing or unreadable file or folder (naming the file and, for a
        folder, the image that failed), an unknown format, frames of unequal
        size, or an array of the wrong shape or type.
    """
    if isinstance(source, np.ndarray):
        return _from_array(source, name or "array")
    path = Path(source)
    label = name or str(path)
    if not path.exists():
        raise DataError("no such file or folder", file=label)
    if path.is_dir():
        return _from_folder(path, label)
    suffix = path.suffix.lower()
    if suffix in _NPZ_SUFFIXES:
        try:
            data = np.load(path, allow_pickle=False)
            arr = data["frames"] if isinstance(data, np.lib.npyio.NpzFile) else data
        except (OSError, ValueError, KeyError) as exc:
            raise DataError(f"cannot read frames: {exc}", file=label) from None
        return _from_array(np.asarray(arr), label)
    if suffix in IMAGE_SUFFIXES:
        return _from_array(_read_image(path, label)[None], label)
    return _from_video(path, label)


def stored_fps(source) -> float | None:
    """The frame rate an ``.npz`` clip carries (a scalar ``fps`` entry, as ``RenderedClip.save`` writes it),
    or None (another kind of clip, no such entry, or an unreadable file: reading the frames reports that)."""
    if not isinstance(source, str | Path) or Path(source).suffix.lower() not in _NPZ_SUFFIXES:
        return None
    try:
        with np.load(source, allow_pickle=False) as data:
            if "fps" not in data.files or np.asarray(data["fps"]).size != 1:
                return None
            fps = float(np.asarray(data["fps"]).ravel()[0])
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        return None
    return fps


def _from_array(arr: np.ndarray, label: str) -> np.ndarray:
    if arr.dtype.kind not in "uif" or arr.dtype == np.bool_:
        raise DataError(f"frames must be numbers; got dtype {arr.dtype}", file=label)
    if arr.ndim == 4 and arr.shape[-1] in (3, 4):
        arr = _to_grey(arr[..., :3])
    elif arr.ndim == 4 and arr.shape[-1] == 1:
        arr = arr[..., 0]
    if arr.ndim != 3:
        raise DataError(f"frames must be (t, h, w) or (t, h, w, 3); got shape {arr.shape}", file=label)
    if arr.shape[0] == 0 or arr.shape[1] < 8 or arr.shape[2] < 8:
        raise DataError(f"no frames, or frames smaller than 8 x 8 pixels: shape {arr.shape}", file=label)
    if arr.dtype == np.uint8:
        return np.ascontiguousarray(arr)
    a = arr.astype(np.float64)
    if not np.isfinite(a).all():
        bad = int(np.argmax(~np.isfinite(a).reshape(a.shape[0], -1).all(axis=1)))
        raise DataError(f"frame {bad} has NaN or infinite pixels", file=label)
    if arr.dtype.kind == "f" and a.max() <= 1.0 and a.min() >= 0.0:
        a = a * 255.0  # floating-point images in [0, 1]
    elif a.max() > 255.0:
        a = a * (255.0 / a.max())  # 16-bit (or wider) frames: scale by the clip's largest value
    return np.clip(np.rint(a), 0, 255).astype(np.uint8)


def _to_grey(rgb: np.ndarray) -> np.ndarray:
    w = np.array([0.299, 0.587, 0.114])
    return rgb.astype(np.float64) @ w


def _read_image(path: Path, label: str) -> np.ndarray:
    img = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if img is None:
        raise DataError("cannot read the image (damaged or not an image)", file=label)
    if img.ndim == 3:
        img = cv2.cvtColor(img[..., :3], cv2.COLOR_BGR2GRAY)
    return img


def _frame_number(path: Path) -> tuple[int, str]:
    digits = re.findall(r"\d+", path.stem)
    return (int(digits[-1]) if digits else -1, path.name)


def _from_folder(path: Path, label: str) -> np.ndarray:
    files = sorted((p for p in path.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES), key=_frame_number)
    if not files:
        raise DataError(f"no images ({', '.join(IMAGE_SUFFIXES)}) in the folder", file=label)
    frames = []
    for k, f in enumerate(files):
        img = _read_image(f, f"{label}/{f.name}")
        if frames and img.shape != frames[0].shape:
            raise DataError(f"frame {k} is {img.shape[1]} x {img.shape[0]} pixels; the first is "
                            f"{frames[0].shape[1]} x {frames[0].shape[0]}", file=f"{label}/{f.name}")
        frames.append(img)
    return _from_array(np.stack(frames), label)


def _from_video(path: Path, label: str) -> np.ndarray:
    cap = cv2.VideoCapture(str(path))
    try:
        if not cap.isOpened():
            raise DataError("cannot open the video (unknown format or damaged file)", file=label)
        frames = []
        while True:
            ok, img = cap.read()
            if not ok:
                break
            frames.append(cv2.cvtColor(img, cv2.COLOR_BGR2GRAY) if img.ndim == 3 else img)
    finally:
        cap.release()
    if not frames:
        raise DataError("the video has no readable frame (damaged file or unsupported codec)", file=label)
    return _from_array(np.stack(frames), label)
