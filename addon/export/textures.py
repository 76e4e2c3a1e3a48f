"""Blender images -> RGBA pixel arrays for bounce_texture_set."""
from dataclasses import dataclass

import numpy as np

from .. import native

# Byte images in these colour spaces hold linear values; every other byte image is decoded as sRGB.
_LINEAR_COLORSPACES = {"Non-Color", "Raw", "Linear", "Linear Rec.709", "Linear CIE-XYZ E", "Linear Rec.2020"}


@dataclass
class ImagePixels:
    width: int
    height: int
    format: int          # native.TEXTURE_*
    pixels: np.ndarray   # width*height*4, uint8 or float32, bottom row first


def read_image(image, reports):
    """The pixels of an image, or None when it has none (missing file, empty image); None is reported."""
    image = image.original
    width, height = image.size  # loads the image if needed
    if width * height == 0:
        where = f" ({image.filepath})" if image.filepath else ""
        reports.warn(f"Image '{image.name}'{where} could not be loaded: drawn magenta")
        return None
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    if image.is_float:
        return ImagePixels(width, height, native.TEXTURE_RGBA32F, pixels)
    # Byte images: `pixels` gives the stored bytes / 255, in the image's own colour space.
    colorspace = image.colorspace_settings.name
    if colorspace in _LINEAR_COLORSPACES:
        texture_format = native.TEXTURE_RGBA8_LINEAR
    else:
        texture_format = native.TEXTURE_RGBA8_SRGB
        if colorspace != "sRGB":
            reports.warn(f"Image '{image.name}': colour space '{colorspace}' is decoded as sRGB")
    bytes_ = np.rint(np.clip(pixels, 0.0, 1.0) * 255.0).astype(np.uint8)
    return ImagePixels(width, height, texture_format, bytes_)
