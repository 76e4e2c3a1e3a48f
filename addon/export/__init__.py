"""Blender -> native scene export: evaluated depsgraph to flat arrays and C API calls.

`SceneSync` is the entry point; the other modules each convert one kind of data and know nothing of the sync.
"""
from .camera import CameraError, final_camera, render_size, viewport_camera
from .reports import Reports, failures_reported
from .scene import SceneSync
from .stats import SyncStats

__all__ = ["CameraError", "Reports", "SceneSync", "SyncStats", "failures_reported", "final_camera", "render_size",
           "viewport_camera"]
