"""What a Blender user sees of a scene-linear image (numpy only, so Blender-side and host-side scripts share it)."""
import numpy as np


def srgb(linear):
    """Blender's Standard view transform: clamped to 0..1, then the sRGB curve."""
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)
