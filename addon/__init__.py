"""Bounce: a Blender render engine for real-time diffuse global illumination.

The native core (libbounce, C API in native/include/bounce/bounce.h) renders; this package is the Blender glue:
export (depsgraph -> arrays), native (ctypes), final and viewport rendering, properties, UI and operators.
"""

bl_info = {  # Blender 3.x legacy add-on metadata; 4.2+ reads blender_manifest.toml instead
    "name": "Bounce",
    "author": "Bounce developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > Render Engine",
    "description": "Real-time diffuse global illumination render engine",
    "category": "Render",
}

import bpy

from . import engine, native, operators, properties, session, ui, versioning, viewport

_CLASSES = (
    engine.BounceRenderEngine,
    *operators.CLASSES,
)


def register():
    # The settings need libbounce; without it Bounce still registers and its render panel says why.
    error = native.load_error()
    if error:
        print(f"Bounce: {error}")
    properties.register()
    for cls in _CLASSES:
        bpy.utils.register_class(cls)
    ui.register()
    operators.register_menus()
    versioning.register()


def unregister():
    versioning.unregister()
    viewport.stop_polling()
    session.release_all()
    operators.unregister_menus()
    ui.unregister()
    for cls in reversed(_CLASSES):
        bpy.utils.unregister_class(cls)
    properties.unregister()
