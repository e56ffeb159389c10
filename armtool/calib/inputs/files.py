"""Reading the files of a calibration: why a path is not a readable file, and images read with
their size bounded before they are decoded.

Why: "does not exist" for a path that exists but is a directory, a FIFO or unreadable sends the
user looking for the wrong problem; and a small PNG can declare 100 000 x 100 000 pixels (a
decompression bomb) that OpenCV would try to allocate (10 GB) before failing.
"""

from __future__ import annotations

import os
import stat
import struct
from pathlib import Path
from typing import TYPE_CHECKING

from armtool.calib.limits import MAX_IMAGE_PIXELS
from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

HEADER_BYTES = 64 * 1024  # enough for the PNG IHDR and a JPEG's SOF after its EXIF segments, mostly


def unreadable_reason(path: Path) -> str | None:
    """None if `path` is a regular file we may read; else what it is instead, in a few words."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        return "is a broken symbolic link" if os.path.islink(path) else "does not exist"
    except NotADirectoryError:
        return "does not exist (a part of its path is a file, not a directory)"
    except PermissionError:
        return "cannot be reached (permission denied on a directory above it)"
    except OSError as exc:
        return f"cannot be read ({exc.strerror or exc})"
    except ValueError:  # an embedded NUL byte
        return "is not a valid path (it holds a NUL character)"
    if stat.S_ISDIR(st.st_mode):
        return "is a directory, not a file"
    if not stat.S_ISREG(st.st_mode):
        return "is not a regular file (a FIFO, socket or device)"
    if not os.access(path, os.R_OK):
        return "is not readable (permission denied)"
    return None


def header_size(head: bytes) -> tuple[int, int] | None:
    """(width, height) declared by a PNG or JPEG header, or None when the format is another one
    or the header is cut short (the size is then checked after decoding)."""
    if head[:8] == b"\x89PNG\r\n\x1a\n" and len(head) >= 24 and head[12:16] == b"IHDR":
        w, h = struct.unpack(">II", head[16:24])
        return int(w), int(h)
    if head[:2] == b"\xff\xd8":
        i = 2
        while i + 9 <= len(head):
            if head[i] != 0xFF:
                return None
            marker = head[i + 1]
            if marker in (0xD8, 0x01) or 0xD0 <= marker <= 0xD7:
                i += 2
                continue
            (length,) = struct.unpack(">H", head[i + 2 : i + 4])
            if 0xC0 <= marker <= 0xCF and marker not in (0xC4, 0xC8, 0xCC):
                h, w = struct.unpack(">HH", head[i + 5 : i + 9])
                return int(w), int(h)
            i += 2 + length
    return None


def check_pixels(width: int, height: int, where: str) -> None:
    if width * height > MAX_IMAGE_PIXELS:
        raise ArmtoolError(
            f"image is {width}x{height} pixels, more than the {MAX_IMAGE_PIXELS // 1_000_000} MP armtool reads",
            where,
            "is it really a camera image? scale it down, or check the file",
        )


def read_gray(path: Path) -> NDArray[np.uint8] | None:
    """The image as 8-bit grayscale, or None if OpenCV cannot decode it. Its size is checked
    from the header before decoding (PNG, JPEG) and from the pixels after (other formats);
    ArmtoolError when it is too large or not a readable file."""
    import cv2
    import numpy as np

    reason = unreadable_reason(path)
    if reason is not None:
        raise ArmtoolError(f"image {reason}", str(path))
    try:
        with open(path, "rb") as handle:
            head = handle.read(HEADER_BYTES)
    except OSError as exc:
        raise ArmtoolError(f"cannot read image: {exc.strerror or exc}", str(path)) from None
    size = header_size(head)
    if size is not None:
        check_pixels(size[0], size[1], str(path))
    gray = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    if gray is None:
        return None
    check_pixels(int(gray.shape[1]), int(gray.shape[0]), str(path))
    return np.asarray(gray, dtype=np.uint8)


def decode_gray_bytes(data: bytes, where: str) -> NDArray[np.uint8] | None:
    """An encoded image held in memory (a bag message), bounded as `read_gray`."""
    import cv2
    import numpy as np

    size = header_size(data[:HEADER_BYTES])
    if size is not None:
        check_pixels(size[0], size[1], where)
    gray = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_GRAYSCALE)
    if gray is None:
        return None
    check_pixels(int(gray.shape[1]), int(gray.shape[0]), where)
    return np.asarray(gray, dtype=np.uint8)
