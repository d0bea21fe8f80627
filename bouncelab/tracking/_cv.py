"""OpenCV, or an ImportError that says how to install it (the ``video`` extra)."""

try:
    import cv2
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise ImportError(
        "bouncelab.tracking needs OpenCV: pip install 'bouncelab[video]' (opencv-python-headless)"
    ) from exc

__all__ = ["cv2"]
