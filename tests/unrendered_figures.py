"""A stand-in for jointwear.report.style.to_png_bytes in tests that read results and text, not pictures."""

from __future__ import annotations

import io

from PIL import Image


def _placeholder_png() -> bytes:
    buf = io.BytesIO()
    Image.new("L", (3, 2), 128).save(buf, format="PNG")  # unlike any PNG a test writes itself
    return buf.getvalue()


PLACEHOLDER_PNG = _placeholder_png()


def unrendered(fig, *, dpi: int = 0, close: bool = True) -> bytes:
    """The figure was made from the data; its pixels are not drawn (the project's figures are off pyplot: nothing
    to close)."""
    return PLACEHOLDER_PNG
