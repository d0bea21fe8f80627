"""Any video FFmpeg reads, through PyAV (the ``video`` extra): grey frames at the stream's bit depth and
the stream's timestamps (``pts * time_base``).

A video container's timestamps are the container's, often at a playback rate
(an export of a 5000 frames/s recording at 25 frames/s), so they do not give
the camera's frame rate: tracking still needs it. What they do show is a frame
that is missing (a gap of whole frame periods), which the tracker keeps.
Streams of more than 8 bits a pixel (FFV1, 10- or 12-bit codecs, 16-bit grey)
are read as 16-bit grey, not rounded to 8 bits.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from bouncelab.core.errors import DataError

__all__ = ["AVVideo", "have_pyav"]


def have_pyav() -> bool:
    """Whether PyAV is installed."""
    try:
        import av  # noqa: F401
    except ImportError:
        return False
    return True


def _ffmpeg_errors() -> tuple[type[BaseException], ...]:
    import av

    errors: list[type[BaseException]] = [OSError, ValueError]
    for name in ("FFmpegError", "AVError"):
        err = getattr(av, name, None) or getattr(getattr(av, "error", None), name, None)
        if isinstance(err, type):
            errors.append(err)
    return tuple(errors)


def wanted_frames(video: Any, wanted: Iterable[int] | None,
                  decode: Callable[[set[int] | None, int], Iterator[tuple[int, np.ndarray]]]
                  ) -> Iterator[tuple[int, np.ndarray]]:
    """``(k, frame)`` for the frames ``wanted`` of ``video`` (default all), in order: from ``video.prefetched``
    when it holds them all (frames read once, for the background: dropped then), else
    ``decode(the frames wanted as a set or None for all, the last frame wanted)`` (a video's ``n`` frames)."""
    want = None if wanted is None else sorted(set(wanted))
    if want is not None and video.prefetched and all(k in video.prefetched for k in want):
        frames, video.prefetched = video.prefetched, {}  # read once (for the background): not kept after
        for k in want:
            yield k, frames.pop(k)
        return
    yield from decode(None if want is None else set(want), video.n - 1 if want is None else max(want, default=-1))


class AVVideo:
    """A video file decoded with PyAV: its frames (grey) in order, in passes, and its timestamps.

    The first pass (at construction) decodes every frame: it counts them (a
    container's count can be an estimate), takes their timestamps, keeps them
    all if they take at most ``keep_bytes`` and otherwise keeps the frames
    ``prefetch(declared count)`` asks for.
    """

    def __init__(self, path: Path, label: str, prefetch: Callable[[int], Iterable[int]] | None,
                 keep_bytes: int) -> None:
        try:
            import av
        except ImportError:
            raise ImportError("reading video with PyAV needs it installed: pip install 'bouncelab[video]' (av), "
                              "or set bouncelab.tracking.frames.VIDEO_READER = 'opencv'") from None

        self.path, self.label = path, label
        errors = _ffmpeg_errors()
        try:
            container = av.open(str(path))
        except errors as exc:
            raise DataError(f"cannot open the video (unknown format or damaged file): {exc}", file=label) from None
        try:
            if not container.streams.video:
                raise DataError("the file has no video stream", file=label)
            stream = container.streams.video[0]
            self.declared = int(stream.frames or 0)
            self.h, self.w = int(stream.codec_context.height), int(stream.codec_context.width)
            rate = stream.average_rate or stream.guessed_rate
            self.container_fps = float(rate) if rate else None
            self.time_base = float(stream.time_base) if stream.time_base else None
            want = set(prefetch(self.declared)) if self.declared and prefetch is not None else set()
            self.prefetched: dict[int, np.ndarray] = {}
            kept: list[np.ndarray] | None = []
            pts: list[float | None] = []
            self.deep: bool | None = None
            try:
                for frame in container.decode(stream):
                    img = self._grey(frame)
                    if kept is not None and (len(pts) + 1) * img.nbytes > keep_bytes:
                        kept = None  # too long to keep: stream it
                    if kept is not None:
                        kept.append(img)
                    if len(pts) in want:
                        self.prefetched[len(pts)] = img
                    pts.append(None if frame.pts is None else float(frame.pts))
            except errors as exc:
                if not pts:
                    raise DataError(f"the video has no readable frame (damaged file or unsupported codec): {exc}",
                                    file=label) from None
                self.damaged = str(exc)
            else:
                self.damaged = None
        finally:
            container.close()
        n = len(pts)
        if n == 0:
            raise DataError("the video has no readable frame (damaged file or unsupported codec)", file=label)
        if self.declared and n < self.declared - 1:
            raise DataError(f"the video holds {n} readable frames of the {self.declared} its header declares "
                            "(truncated or damaged file)", file=label)
        if n != self.declared:
            self.prefetched = {}  # read for a count that was not the real one
        self.n = n
        self.kept = kept
        self.times: np.ndarray | None = None
        if self.time_base and all(p is not None for p in pts):
            t = np.asarray(pts, dtype=float) * self.time_base
            if n < 2 or (np.diff(t) > 0).all():
                self.times = t

    def _grey(self, frame) -> np.ndarray:
        """A decoded frame as grey: uint8, or uint16 for a stream of more than 8 bits a pixel."""
        if self.deep is None:
            bits = max((c.bits for c in frame.format.components), default=8)
            self.deep = bits > 8
            self.bit_depth = int(bits)
        return frame.to_ndarray(format="gray16le" if self.deep else "gray")

    @property
    def dtype(self) -> np.dtype:
        return np.dtype(np.uint16) if self.deep else np.dtype(np.uint8)

    def frames(self, wanted: Iterable[int] | None) -> Iterator[tuple[int, np.ndarray]]:
        """``(k, grey frame)`` for the frames ``wanted`` (default all), in order, decoding the file again."""
        return wanted_frames(self, wanted, self._decode)

    def _decode(self, wanted_set: set[int] | None, last: int) -> Iterator[tuple[int, np.ndarray]]:
        import av

        errors = _ffmpeg_errors()
        k = -1
        try:
            with av.open(str(self.path)) as container:
                for k, frame in enumerate(container.decode(container.streams.video[0])):
                    if k > last:
                        break
                    if wanted_set is None or k in wanted_set:
                        img = self._grey(frame)
                        if img.shape != (self.h, self.w):
                            raise DataError(f"frame {k} is {img.shape[1]} x {img.shape[0]} pixels; the video "
                                            f"declares {self.w} x {self.h}", file=self.label)
                        yield k, img
        except errors as exc:
            raise DataError(f"the video could be read to its end once but not again at frame {k + 1} "
                            f"(changed or damaged file): {exc}", file=self.label) from None
        if k < last:
            raise DataError(f"the video could be read to its end once but not again at frame {k + 1} "
                            "(changed or damaged file)", file=self.label)
