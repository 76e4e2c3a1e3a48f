"""Extension check, Blender side (4.2+): Blender was started WITHOUT scripts/blender and without
--factory-startup, so Bounce can only come from the extension installed in $BLENDER_USER_RESOURCES. Records which
add-on modules are enabled and which module the BOUNCE engine class lives in, builds the demo scene and renders
it to OUT/demo.exr.

    BLENDER_USER_RESOURCES=U blender -b --python ext_render.py -- OUT
"""
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common as bc  # noqa: E402

out = bc.args()[0]
engines = {getattr(cls, "bl_idname", None): cls.__module__ for cls in bpy.types.RenderEngine.__subclasses__()}
info = {"addons": sorted(bpy.context.preferences.addons.keys()), "engine_module": engines.get("BOUNCE"),
        "user_resources": os.environ.get("BLENDER_USER_RESOURCES")}
print("extension check:", info)
if "BOUNCE" in engines:
    factory = bpy.context.scene
    bpy.ops.bounce.demo_scene(resolution=64)
    scene = next(s for s in bpy.data.scenes if s != factory)
    bc.linear_output(scene)
    scene.bounce.samples = 4
    info["exr"] = bc.render_still(scene, os.path.join(out, "demo"))
bc.write_json(os.path.join(out, "ext.json"), info)
