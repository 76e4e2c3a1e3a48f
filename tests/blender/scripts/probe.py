"""Probe: Blender version and whether the Bounce add-on loaded.   blender -b --python probe.py -- OUT.json"""
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common as bc  # noqa: E402

props = getattr(bpy.context.scene, "bounce", None)
settings = sorted(k for k in props.bl_rna.properties.keys() if k != "rna_type") if props is not None else []
engines = [getattr(e, "bl_idname", None) for e in bpy.types.RenderEngine.__subclasses__()]
bc.write_json(bc.args()[0], {
    "version": list(bpy.app.version),
    "version_string": bpy.app.version_string,
    "engine_registered": "BOUNCE" in engines,
    "settings": settings,
    "python": sys.version.split()[0],
})
print("probe:", bpy.app.version_string, "BOUNCE" in engines, settings)
