"""Packed pixels of camera files: 10 bits (4 pixels in 5 bytes) and 12 bits (2 pixels in 3 bytes).

Both cameras' formats pack the bits most significant first: a 12-bit pair ``a, b``
is stored as the bytes ``a >> 4``, ``(a & 0xF) << 4 | b >> 8``, ``b & 0xFF``
(Phantom's ``BI_PACKED_12P`` and Photron's 12-bit ``.mraw``); four 10-bit pixels
fill five bytes the same way (Phantom's ``BI_PACKED``). The unpacked values are
the stored ones (0 to 1023, 0 to 4095), not shifted to 16 bits.
"""

from __future__ import annotations

import numpy as np

__all__ = ["PACKED_BITS", "pack", "packed_bytes", "unpack"]

#: Packed widths: bits per pixel -> (pixels, bytes) of one group.
PACKED_BITS = {10: (4, 5), 12: (2, 3)}


def packed_bytes(n_pixels: int, bits: int) -> int:
    """Bytes that ``n_pixels`` packed pixels of ``bits`` bits take (``n_pixels`` a whole number of groups)."""
    pixels, nbytes = PACKED_BITS[bits]
    return n_pixels // pixels * nbytes


def unpack(buf: np.ndarray, bits: int) -> np.ndarray:
    """The uint16 pixels of the packed bytes ``buf`` (a whole number of groups of :data:`PACKED_BITS`)."""
    pixels, nbytes = PACKED_BITS[bits]
    b = np.asarray(buf, dtype=np.uint8).reshape(-1, nbytes).astype(np.uint16)
    out = np.empty((b.shape[0], pixels), np.uint16)
    if bits == 12:
        out[:, 0] = (b[:, 0] << 4) | (b[:, 1] >> 4)
        out[:, 1] = ((b[:, 1] & 0x0F) << 8) | b[:, 2]
    else:
        out[:, 0] = (b[:, 0] << 2) | (b[:, 1] >> 6)
        out[:, 1] = ((b[:, 1] & 0x3F) << 4) | (b[:, 2] >> 4)
        out[:, 2] = ((b[:, 2] & 0x0F) << 6) | (b[:, 3] >> 2)
        out[:, 3] = ((b[:, 3] & 0x03) << 8) | b[:, 4]
    return out.reshape(-1)


def pack(values: np.ndarray, bits: int) -> np.ndarray:
    """The packed bytes of ``values`` (integers below ``2**bits``; a whole number of groups)."""
    pixels, nbytes = PACKED_BITS[bits]
    v = np.asarray(values).reshape(-1, pixels).astype(np.uint16)
    out = np.empty((v.shape[0], nbytes), np.uint8)
    if bits == 12:
        out[:, 0] = v[:, 0] >> 4
        out[:, 1] = ((v[:, 0] & 0x0F) << 4) | (v[:, 1] >> 8)
        out[:, 2] = v[:, 1] & 0xFF
    else:
        out[:, 0] = v[:, 0] >> 2
        out[:, 1] = ((v[:, 0] & 0x03) << 6) | (v[:, 1] >> 4)
        out[:, 2] = ((v[:, 1] & 0x0F) << 4) | (v[:, 2] >> 6)
        out[:, 3] = ((v[:, 2] & 0x3F) << 2) | (v[:, 3] >> 8)
        out[:, 4] = v[:, 3] & 0xFF
    return out.reshape(-1)
